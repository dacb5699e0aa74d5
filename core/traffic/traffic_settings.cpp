#include "traffic/traffic_settings.hpp"

#include <algorithm>

#include "traffic/one_way.hpp"

namespace fleet::traffic {

TrafficConfiguration configuration_from(const config::FleetConfig& config) {
  TrafficConfiguration c;
  c.resources.footprint = {0.0, 0.0};
  for (const auto& fleet : config.fleets) {
    c.resources.footprint.length = std::max(c.resources.footprint.length, fleet.footprint.length);
    c.resources.footprint.width = std::max(c.resources.footprint.width, fleet.footprint.width);
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

map::RoadGraph planning_graph(const map::RoadGraph& graph, const TrafficConfiguration& configuration) {
  if (!configuration.one_way) return graph;
  const ConflictZones zones(graph, configuration.resources);
  return one_way_plan(graph, zones).graph;
}

}  // namespace fleet::traffic
