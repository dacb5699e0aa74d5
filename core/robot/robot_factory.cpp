#include "robot/robot_factory.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string_view>

#include "robot/forklift/forklift.hpp"
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

traffic::TrafficConfiguration traffic_configuration_with_drives(const config::FleetConfig& config) {
  traffic::TrafficConfiguration configuration = traffic::configuration_from(config);
  for (std::size_t type = 0; type < config.fleets.size(); ++type) {
    traffic::VehicleType& vehicle = configuration.resources.vehicle_types.at(type);
    if (vehicle.drive) continue;
    const control::FollowerParams follower = follower_params(config, config.fleets[type]);
    vehicle.drive = [follower](const std::vector<geometry::Vec2>& path, bool) {
      return follower_drive(follower, path);
    };
  }
  return configuration;
}

// Traffic grants two robots places only where their bodies stay traffic::reservation_margin
// apart. A robot that refused to drive on beside another at that gap would wait for it with the
// road granted to both, and the other likewise. The look ahead therefore keeps half of it to the
// bodies other robots report: the other half is for both robots' estimates being off.
double lookahead_gap(const config::FleetConfig& config) {
  return traffic::reservation_margin(config) / 2.0;
}

std::uint64_t noise_stream_of(const std::string& robot_id) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (char c : robot_id) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  return h % 1000003 * 16;
}

double fastest_fleet_speed(const config::FleetConfig& config) {
  double fastest = 0.0;
  for (const auto& fleet : config.fleets) fastest = std::max(fastest, fleet.profile.max_speed);
  return fastest;
}

// Each type's builder lives in its folder (core/robot/<type>/<type>_robot.cpp).
#define FLEET_ROBOT_TYPE(name) std::unique_ptr<Robot> make_##name(const RobotBuild& build);
#include "robot/robot_types.def"
#undef FLEET_ROBOT_TYPE

std::unique_ptr<Robot> make_robot(const config::FleetSpec& fleet, const config::FleetConfig& config,
                                  std::shared_ptr<const map::SiteMap> site, const geometry::Pose2& home,
                                  std::uint64_t seed, std::uint64_t stream) {
  using Builder = std::unique_ptr<Robot> (*)(const RobotBuild&);
  static const std::map<std::string_view, Builder> builders{
#define FLEET_ROBOT_TYPE(name) {#name, &make_##name},
#include "robot/robot_types.def"
#undef FLEET_ROBOT_TYPE
  };
  const auto it = builders.find(fleet.robot_type);
  if (it == builders.end()) {
    throw std::invalid_argument("fleet '" + fleet.id + "': unknown robot type '" + fleet.robot_type +
                                "' (known: " + vehicle::robot_type_names() + ")");
  }
  return it->second({fleet, config, std::move(site), home, seed, stream});
}

}  // namespace fleet::robot
