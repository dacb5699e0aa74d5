#include "server/site_derivation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

#include "test_paths.hpp"
#include "traffic/traffic_settings.hpp"

using namespace fleet;

namespace {

std::string refusal(const map::Site& current, const std::string& map_id, const config::FleetConfig& config) {
  try {
    server::load_revision(current, map_id, config);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SiteDerivation, ARevisionIsDerivedWithItsNamesTravelAndTrafficManager) {
  const map::SiteMap table_a = map::load_site_map(fleet::test::source_path("/maps/table_a.yaml"));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  config.settings.set("traffic.enabled", "true", "site_derivation_test");
  const server::SiteDerivation closed = server::load_revision(table_a.site, "table_a_north_closed", config);
  ASSERT_NE(closed.site_map, nullptr);
  EXPECT_EQ(closed.site_map->site.name, "table_a_north_closed");
  EXPECT_LT(closed.site_map->graph.graph.points.size(), table_a.graph.graph.points.size());
  ASSERT_NE(closed.traffic, nullptr);
  EXPECT_GT(closed.traffic->zones().place_count(), 0);
  for (const auto& fleet : config.fleets) EXPECT_TRUE(closed.travel.contains(fleet.id)) << fleet.id;
  EXPECT_FALSE(closed.known_names->abilities.empty());

  config.settings.set("traffic.enabled", "false", "site_derivation_test");
  EXPECT_EQ(server::derive_site(closed.site_map, config).traffic, nullptr);
}

// traffic.core places derives the coordination core instead of the traffic manager; it lets the
// robots drive the lanes their agents plan on: every lane both ways (the default), the corridors
// on cycles one way with traffic.places_one_way. The manager's traffic.one_way does not apply.
TEST(SiteDerivation, ThePlacesCoreIsDerivedInsteadOfTheManager) {
  const auto table_a =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/table_a.yaml")));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  config.settings.set("traffic.enabled", "true", "site_derivation_test");
  config.settings.set("traffic.core", "places", "site_derivation_test");
  auto edges = [](const map::RoadGraph& graph) {
    std::size_t count = 0;
    for (const auto& out : graph.successors) count += out.size();
    return count;
  };
  const server::SiteDerivation derived = server::derive_site(table_a, config);
  EXPECT_EQ(derived.traffic, nullptr);
  ASSERT_NE(derived.places, nullptr);
  EXPECT_GT(derived.places->zones.place_count(), 0u);
  EXPECT_EQ(derived.places->robot_types.size(), config.all_robots().size());
  EXPECT_GT(derived.places->traffic.plan_period_s(), 0.0);
  EXPECT_FALSE(traffic::configuration_from(config).one_way);
  EXPECT_EQ(edges(derived.places->lanes), edges(table_a->graph.graph)) << "every lane both ways";

  config.settings.set("traffic.places_one_way", "true", "site_derivation_test");
  config.settings.set("traffic.one_way", "false", "site_derivation_test");
  const server::SiteDerivation one_way = server::derive_site(table_a, config);
  ASSERT_NE(one_way.places, nullptr);
  EXPECT_LT(edges(one_way.places->lanes), edges(table_a->graph.graph)) << "corridors on cycles one way";
}

TEST(SiteDerivation, AMapThatIsMissingOrNotARevisionIsRefusedWithTheReason) {
  const map::SiteMap table_a = map::load_site_map(fleet::test::source_path("/maps/table_a.yaml"));
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  const std::string missing = refusal(table_a.site, "table_z", config);
  EXPECT_NE(missing.find("map 'table_z' cannot be loaded"), std::string::npos) << missing;
  EXPECT_NE(missing.find("table_z.yaml"), std::string::npos) << missing;
  const std::string other_site = refusal(table_a.site, "table_b", config);
  EXPECT_FALSE(other_site.empty());
  EXPECT_EQ(other_site, map::revision_mismatch(
                            table_a.site, map::load_site_map(fleet::test::source_path("/maps/table_b.yaml")).site));
}

TEST(SiteDerivation, ASwitchIsRefusedWhileARobotStandsOnARoadTheNewMapCloses) {
  const map::SiteMap table_a = map::load_site_map(fleet::test::source_path("/maps/table_a.yaml"));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  const server::SiteDerivation closed = server::load_revision(table_a.site, "table_a_north_closed", config);
  const auto& new_points = closed.site_map->graph.graph.points;
  auto kept = [&](const auto& p) {
    return std::any_of(new_points.begin(), new_points.end(), [&](const auto& q) {
      return geometry::distance({p.x, p.y}, {q.x, q.y}) <= 0.02;
    });
  };
  const auto& old_points = table_a.graph.graph.points;
  const auto gone = std::find_if(old_points.begin(), old_points.end(), [&](const auto& p) { return !kept(p); });
  const auto stays = std::find_if(old_points.begin(), old_points.end(), kept);
  ASSERT_NE(gone, old_points.end());
  ASSERT_NE(stays, old_points.end());

  const std::string refused = server::robot_on_closed_road(
      table_a, *closed.site_map, "table_a_north_closed", {{"fl2", {stays->x, stays->y}}, {"fl1", {gone->x, gone->y}}});
  EXPECT_NE(refused.find("robot fl1 stands at"), std::string::npos) << refused;
  EXPECT_NE(refused.find("map 'table_a_north_closed' closes"), std::string::npos) << refused;
  EXPECT_EQ(
      server::robot_on_closed_road(table_a, *closed.site_map, "table_a_north_closed", {{"fl2", {stays->x, stays->y}}}),
      "");
}
