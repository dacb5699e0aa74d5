#include "traffic/traffic_settings.hpp"

#include <algorithm>

#include "traffic/one_way.hpp"
#include "traffic/vehicle_lanes.hpp"

namespace fleet::traffic {

geometry::Polygon footprint_polygon_of(const config::FleetSpec& fleet) {
  return fleet.profile.footprint;
}

TrafficConfiguration configuration_from(const config::FleetConfig& config) {
  TrafficConfiguration c;
  // The largest footprint stays the one-type fallback for a configuration without fleets.
  c.resources.footprint = {0.0, 0.0};
  for (const auto& fleet : config.fleets) {
    c.resources.footprint.length = std::max(c.resources.footprint.length, fleet.footprint.length);
    c.resources.footprint.width = std::max(c.resources.footprint.width, fleet.footprint.width);
    const int type = static_cast<int>(c.resources.vehicle_types.size());
    c.resources.vehicle_types.push_back({fleet.id, footprint_polygon_of(fleet)});
    for (const auto& robot : fleet.robots) c.robot_vehicle_types[robot.id] = type;
  }
  const auto& s = config.settings;
  c.resources.margin = s.get_double("traffic.margin");
  c.lookahead = s.get_double("traffic.lookahead");
  c.priority_wait = s.get_double("traffic.priority_wait_s");
  c.reroute_wait = s.get_double("traffic.reroute_wait_s");
  c.lost_reroute_wait = s.get_double("traffic.lost_reroute_wait_s");
  c.one_way = s.get_bool("traffic.one_way");
  return c;
}

int vehicle_type_of(const config::FleetConfig& config, const std::string& fleet_id) {
  for (std::size_t i = 0; i < config.fleets.size(); ++i) {
    if (config.fleets[i].id == fleet_id) return static_cast<int>(i);
  }
  return 0;
}

map::RoadGraph planning_graph(const map::RoadGraph& graph, const TrafficConfiguration& configuration, int type) {
  const ConflictZones zones(graph, configuration.resources);
  const VehicleType& vehicle = zones.vehicle_types().at(static_cast<std::size_t>(type));
  const double width = footprint_width(vehicle.footprint);
  if (!configuration.one_way) return lane_graph_for(graph, width, configuration.resources.margin);
  return lane_graph_for(one_way_plan(graph, zones).graph, width, configuration.resources.margin);
}

}  // namespace fleet::traffic
