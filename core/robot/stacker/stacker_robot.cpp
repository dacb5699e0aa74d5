// The stacker's software as the agent builds it (its half of the type table,
// core/robot/robot_types.def).
#include <algorithm>

#include "robot/robot_factory.hpp"
#include "robot/stacker/stacker.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::robot {

namespace {

StackerConfig stacker_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                             const map::SiteMap& site) {
  StackerConfig c = StackerConfig::for_vehicle(fleet.profile);
  c.pursuit.max_speed = config.top_speed(fleet);
  c.neighbour_max_speed = std::max(c.neighbour_max_speed, fastest_fleet_speed(config));
  c.traffic = config.settings.get_bool("traffic.enabled");
  if (c.traffic) {
    c.clearance_margin = std::min(c.clearance_margin, lookahead_gap(config));
    c.safety_gap = std::min(c.safety_gap, lookahead_gap(config) / 2.0);
  }
  // Only the lanes a stacker fits, traffic or not: its bays are no lanes to drive along, and a
  // stacker cannot turn where its body does not fit.
  c.route_graph = std::make_shared<const map::RoadGraph>(traffic::planning_graph(
      site.graph.graph, traffic::configuration_from(config), traffic::vehicle_type_of(config, fleet.id)));
  return c;
}

}  // namespace

std::unique_ptr<Robot> make_stacker(const RobotBuild& build) {
  return std::make_unique<Stacker>(stacker_config(build.config, build.fleet, *build.site), build.site, build.home,
                                   build.seed, build.stream);
}

}  // namespace fleet::robot
