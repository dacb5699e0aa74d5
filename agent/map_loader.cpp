#include "agent/map_loader.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <chrono>

#include "map/site.hpp"
#include "robot/robot_factory.hpp"

namespace fleet::agent {

namespace {

/// The reading thread yields the cores to the control loops of this and the other agents
/// (Linux gives each thread its own nice value).
void lower_this_threads_priority() {
  constexpr int kReaderNice = 10;
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), kReaderNice);
}

LoadedMap read_map(const config::FleetConfig& config, const config::FleetSpec& fleet, const std::string& maps_dir,
                   const std::string& map_id) {
  lower_this_threads_priority();
  LoadedMap loaded{map_id, nullptr, nullptr, ""};
  try {
    auto site = std::make_shared<const map::SiteMap>(map::load_site_map(map::site_path(maps_dir, map_id)));
    loaded.route_graph = robot::route_graph_for(config, fleet, *site);
    loaded.site = std::move(site);
  } catch (const std::exception& e) {
    loaded.error = e.what();
  }
  return loaded;
}

}  // namespace

MapLoader::MapLoader(const config::FleetConfig& config, const config::FleetSpec& fleet, std::string maps_dir)
    : config_(config), fleet_(fleet), maps_dir_(std::move(maps_dir)) {}

MapLoader::~MapLoader() {
  if (task_.valid()) task_.wait();
}

void MapLoader::request(const std::string& map_id) {
  wanted_ = map_id;
  if (!task_.valid()) start(map_id);
}

void MapLoader::start(const std::string& map_id) {
  task_ = std::async(std::launch::async, read_map, std::cref(config_), std::cref(fleet_), maps_dir_, map_id);
}

std::optional<LoadedMap> MapLoader::take() {
  if (!task_.valid() || task_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
  LoadedMap loaded = task_.get();
  if (loaded.map_id != wanted_) {
    // Asked for another map meanwhile: this one is of no use any more.
    start(wanted_);
    return std::nullopt;
  }
  wanted_.clear();
  return loaded;
}

}  // namespace fleet::agent
