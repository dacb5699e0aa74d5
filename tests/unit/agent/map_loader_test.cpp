#include "agent/map_loader.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "common/paths.hpp"

namespace fleet::agent {
namespace {

config::FleetConfig plant_config() {
  return config::load_fleet_config(site_config_path("plant"));
}

/// What the loader hands over within `limit`, polled as the agent's loop polls it.
std::optional<LoadedMap> wait_for(MapLoader& loader, std::chrono::seconds limit = std::chrono::seconds(30)) {
  const auto until = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < until) {
    if (auto loaded = loader.take()) return loaded;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return std::nullopt;
}

TEST(MapLoader, ReadsTheAssignedMapAndTheFleetsRouteGraphOffTheCallersThread) {
  const auto config = plant_config();
  MapLoader loader(config, config.fleets.front(), maps_dir());
  EXPECT_FALSE(loader.take());
  loader.request("plant_middle_closed");
  EXPECT_EQ(loader.pending(), "plant_middle_closed");
  const auto loaded = wait_for(loader);
  ASSERT_TRUE(loaded);
  EXPECT_EQ(loaded->map_id, "plant_middle_closed");
  ASSERT_TRUE(loaded->site) << loaded->error;
  EXPECT_EQ(loaded->site->site.name, "plant_middle_closed");
  // Under traffic the fleet plans on a graph of its own (one-way corridors, lanes it fits).
  ASSERT_EQ(loaded->route_graph != nullptr, config.settings.get_bool("traffic.enabled"));
  EXPECT_TRUE(loader.pending().empty());
  EXPECT_FALSE(loader.take());  // handed over once
}

TEST(MapLoader, AMapAskedForWhileAnotherIsReadReplacesIt) {
  const auto config = plant_config();
  MapLoader loader(config, config.fleets.front(), maps_dir());
  loader.request("plant_middle_closed");
  loader.request("plant");
  const auto loaded = wait_for(loader);
  ASSERT_TRUE(loaded);
  EXPECT_EQ(loaded->map_id, "plant");
  ASSERT_TRUE(loaded->site) << loaded->error;
  EXPECT_EQ(loaded->site->site.name, "plant");
  EXPECT_FALSE(wait_for(loader, std::chrono::seconds(1)));  // the first one is never handed over
}

TEST(MapLoader, AMapThatCannotBeReadComesBackWithTheReason) {
  const auto config = plant_config();
  MapLoader loader(config, config.fleets.front(), maps_dir());
  loader.request("no_such_plant");
  const auto loaded = wait_for(loader);
  ASSERT_TRUE(loaded);
  EXPECT_FALSE(loaded->site);
  EXPECT_NE(loaded->error.find("no_such_plant"), std::string::npos) << loaded->error;
}

}  // namespace
}  // namespace fleet::agent
