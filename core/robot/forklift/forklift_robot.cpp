// The forklift's software as the agent builds it (its half of the type table,
// core/robot/robot_types.def).
#include "robot/forklift/forklift_robot.hpp"

#include <algorithm>

#include "traffic/traffic_settings.hpp"

namespace fleet::robot {

ForkliftConfig forklift_robot_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                     const map::SiteMap& site) {
  // Sizes, tolerances, gaps and manoeuvre speeds follow the fleet's vehicle (see docs/control.md).
  ForkliftConfig c = ForkliftConfig::for_vehicle(fleet.profile);
  c.sim.forklift.footprint = fleet.footprint;
  c.neighbour_max_speed = std::max(c.neighbour_max_speed, fastest_fleet_speed(config));
  c.task.follower = follower_params(config, fleet);
  c.traffic = config.settings.get_bool("traffic.enabled");
  if (c.traffic) {
    // What the look ahead keeps to the bodies other robots report, within what traffic keeps
    // between the robots it grants places to (see lookahead_gap).
    const double gap = lookahead_gap(config);
    c.clearance_margin = std::min(c.clearance_margin, gap / 2.0);
    c.neighbour_margin = std::min(c.neighbour_margin, gap - c.clearance_margin);
    c.safety_gap = std::min(c.safety_gap, gap / 2.0);
    // The core's places keep the bodies apart: the look ahead's margins are all the stop needs.
    if (config.settings.get_string("traffic.core") == "places") {
      c.planned_stop_distance = 0.0;
      c.stop_outlasts_reroute = true;
    }
  }
  c.route_graph = route_graph_for(config, fleet, site);
  return c;
}

std::unique_ptr<Robot> make_forklift(const RobotBuild& build) {
  return std::make_unique<Forklift>(forklift_robot_config(build.config, build.fleet, *build.site), build.site,
                                    build.home, build.seed, build.stream);
}

}  // namespace fleet::robot
