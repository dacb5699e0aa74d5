#pragma once

#include <future>
#include <memory>
#include <optional>
#include <string>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"

namespace fleet::agent {

/// A map the server assigned, read and turned into the fleet's route graph.
struct LoadedMap {
  std::string map_id;
  std::shared_ptr<const map::SiteMap> site;  ///< null when it could not be read
  std::shared_ptr<const map::RoadGraph> route_graph;
  std::string error;  ///< why it could not be read, else empty
};

/// Reads assigned maps off the control loop. A plant map takes a fifth of a second of CPU to read
/// and to build the route graph from; a dozen agents switching at once on two cores would stand
/// still for over a second, long enough for the server to take every robot for lost. The robot
/// keeps driving (or standing, as traffic tells it) on the old map meanwhile.
class MapLoader {
 public:
  MapLoader(const config::FleetConfig& config, const config::FleetSpec& fleet, std::string maps_dir);
  ~MapLoader();
  MapLoader(const MapLoader&) = delete;
  MapLoader& operator=(const MapLoader&) = delete;

  /// Asks for `map_id`. A map asked for while another is read is read next; only the newest
  /// request is kept.
  void request(const std::string& map_id);
  /// The map read since the last call, once, if the newest request is done; nothing otherwise.
  std::optional<LoadedMap> take();
  /// The map being read or waiting to be, else empty.
  const std::string& pending() const { return wanted_; }

 private:
  void start(const std::string& map_id);

  const config::FleetConfig& config_;
  const config::FleetSpec& fleet_;
  std::string maps_dir_;
  std::string wanted_;  ///< the newest map asked for and not yet taken
  std::future<LoadedMap> task_;
};

}  // namespace fleet::agent
