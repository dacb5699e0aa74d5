#include "robot/robot_factory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "robot/forklift.hpp"
#include "robot/stacker.hpp"
#include "sim/summit_xls.hpp"
#include "traffic/traffic_settings.hpp"
#include "vehicle/vehicle_types.hpp"

namespace fleet::robot {

std::shared_ptr<const map::RoadGraph> route_graph_for(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                                      const map::SiteMap& site) {
  if (!config.settings.get_bool("traffic.enabled")) return nullptr;
  return std::make_shared<const map::RoadGraph>(traffic::planning_graph(
      site.graph.graph, traffic::configuration_from(config), traffic::vehicle_type_of(config, fleet.id)));
}

control::FollowerParams follower_params(const config::FleetConfig& config, const config::FleetSpec& fleet) {
  control::FollowerParams f = ForkliftConfig::for_vehicle(fleet.profile).task.follower;
  f.v_max = config.top_speed(fleet);
  f.omega_max = std::min(config.settings.get_double("agent.max_yaw_rate"), fleet.profile.max_yaw_rate);
  return f;
}

std::vector<geometry::Pose2> follower_drive(const control::FollowerParams& params,
                                            const std::vector<geometry::Vec2>& path) {
  if (path.size() < 2) return {};
  std::vector<geometry::Pose2> poses;
  double length = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const geometry::Vec2 along = i + 1 < path.size() ? path[i + 1] - path[i] : path[i] - path[i - 1];
    poses.push_back({path[i].x, path[i].y, std::atan2(along.y, along.x)});
    if (i + 1 < path.size()) length += geometry::distance(path[i], path[i + 1]);
  }
  control::PathFollower follower(params);
  follower.set_path(poses);
  geometry::Pose2 pose = poses.front();
  // Coarser than the agent's 70 Hz: a few centimetres a step at top speed, and a place holds the
  // hull of the bodies driven through it.
  constexpr double kDt = 0.05;
  // Time enough to drive the path at a tenth of top speed, with its turns on the spot.
  const int steps = static_cast<int>((10.0 * length / std::max(params.v_max, 0.05) + 20.0) / kDt);
  std::vector<geometry::Pose2> driven{pose};
  for (int k = 0; k < steps && !follower.arrived(); ++k) {
    pose = control::integrate_twist(pose, follower.step({pose, k == 0 ? 0.0 : kDt}), kDt);
    driven.push_back(pose);
  }
  return driven;
}

namespace {

/// Traffic grants two robots places only where their bodies stay traffic::reservation_margin
/// apart. A robot that refused to drive on beside another at that gap would wait for it with the
/// road granted to both, and the other likewise. The look ahead therefore keeps half of it to the
/// bodies other robots report: the other half is for both robots' estimates being off.
double lookahead_gap(const config::FleetConfig& config) {
  return traffic::reservation_margin(config) / 2.0;
}

robot::ForkliftConfig forklift_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                      const map::SiteMap& site) {
  // Sizes, tolerances, gaps and manoeuvre speeds follow the fleet's vehicle (see docs/control.md).
  robot::ForkliftConfig c = robot::ForkliftConfig::for_vehicle(fleet.profile);
  c.sim.forklift.footprint = fleet.footprint;
  // A neighbour not heard from lately may have driven at the top speed of any fleet on the site.
  for (const auto& other : config.fleets) {
    c.neighbour_max_speed = std::max(c.neighbour_max_speed, other.profile.max_speed);
  }
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

robot::StackerConfig stacker_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                    const map::SiteMap& site) {
  robot::StackerConfig c = robot::StackerConfig::for_vehicle(fleet.profile);
  c.pursuit.max_speed = config.top_speed(fleet);
  for (const auto& other : config.fleets) {
    c.neighbour_max_speed = std::max(c.neighbour_max_speed, other.profile.max_speed);
  }
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

/// The picker's base [Picker thesis]: the forklift software without forks on the Summit-XLS, localised by the
/// site's markers and wheel odometry.
robot::ForkliftConfig picker_robot_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                          const map::SiteMap& site) {
  robot::ForkliftConfig c = forklift_config(config, fleet, site);
  c.type_name = "picker";
  c.forks = false;
  c.arm = true;
  // The boom camera over the left side, where the pallet stands at a stop.
  c.box_camera.mount = {0.25, 0.20, 1.50};
  const geometry::Footprint footprint = c.sim.forklift.footprint;
  c.sim.forklift = sim::summit_xls_body_params();
  c.sim.forklift.footprint = footprint;
  c.sim.marker_localization = true;
  return c;
}

std::unique_ptr<Robot> make_robot(const config::FleetSpec& fleet, const config::FleetConfig& config,
                                  std::shared_ptr<const map::SiteMap> site, const geometry::Pose2& home,
                                  std::uint64_t seed, std::uint64_t stream) {
  // One branch per robot type the agent can drive; its software lives in its own file here.
  if (fleet.robot_type == "forklift") {
    return std::make_unique<Forklift>(forklift_config(config, fleet, *site), site, home, seed, stream);
  }
  if (fleet.robot_type == "picker") {
    return std::make_unique<Forklift>(picker_robot_config(config, fleet, *site), site, home, seed, stream);
  }
  if (fleet.robot_type == "stacker") {
    return std::make_unique<Stacker>(stacker_config(config, fleet, *site), site, home, seed, stream);
  }
  throw std::invalid_argument("fleet '" + fleet.id + "': unknown robot type '" + fleet.robot_type +
                              "' (known: " + vehicle::robot_type_names() + ")");
}

}  // namespace fleet::robot
