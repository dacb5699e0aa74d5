#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "config/fleet_config.hpp"
#include "control/path_follower.hpp"
#include "map/site_map.hpp"
#include "robot/navigation.hpp"
#include "robot/robot.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::robot {

/// What make_robot hands the builder of a robot type (make_<type> in core/robot/<type>/).
struct RobotBuild {
  const config::FleetSpec& fleet;
  const config::FleetConfig& config;
  std::shared_ptr<const map::SiteMap> site;
  geometry::Pose2 home;
  std::uint64_t seed = 0;
  std::uint64_t stream = 0;
};

/// The robot of `fleet`'s robot type, at `home` on `site`, configured from the fleet's profile
/// and `config`'s settings; `seed` and `stream` pick its noise. Throws std::invalid_argument
/// naming the type and the known ones (vehicle::robot_types()) when the agent cannot build it.
std::unique_ptr<Robot> make_robot(const config::FleetSpec& fleet, const config::FleetConfig& config,
                                  std::shared_ptr<const map::SiteMap> site, const geometry::Pose2& home,
                                  std::uint64_t seed, std::uint64_t stream);

/// The stream of the run's seed a robot draws its noise from (make_robot's `stream`): each robot
/// its own, from its id.
std::uint64_t noise_stream_of(const std::string& robot_id);

/// The top speed of the fastest fleet's vehicles: how fast a neighbour not heard from lately may
/// have driven, whatever its fleet.
double fastest_fleet_speed(const config::FleetConfig& config);

/// The gap the look ahead keeps to the bodies other robots report when traffic is on: half of
/// what traffic keeps between the robots it grants places to (traffic::reservation_margin).
double lookahead_gap(const config::FleetConfig& config);

/// The path follower of a robot of `fleet` with a mecanum or differential base, as make_robot
/// configures it: scaled to the vehicle, at the fleet's top speed and yaw rate.
control::FollowerParams follower_params(const config::FleetConfig& config, const config::FleetSpec& fleet);

/// The footprint-centre poses of such a robot following `path` with that follower from its first
/// point, heading along its first segment, from rest (traffic::VehicleType::drive): it steers for
/// a point one lookahead on, so it turns before a bend and cuts it.
std::vector<geometry::Pose2> follower_drive(const control::FollowerParams& params,
                                            const std::vector<geometry::Vec2>& path);

/// The traffic configuration of `config` whose vehicle types sweep what their agents' own
/// controllers sweep through the bends: a stacker's pursuit (traffic::configuration_from) and, for
/// mecanum and differential bases, the path follower (follower_drive), which steers for a point
/// one lookahead on (0.64 m for a reach truck), turns before a bend and cuts it.
traffic::TrafficConfiguration traffic_configuration_with_drives(const config::FleetConfig& config);

/// The graph a robot of `fleet` plans on: under traffic, the traffic manager's graph for its
/// fleet's vehicle type (one-way corridors, only the lanes it fits), else none (the site's own).
std::shared_ptr<const map::RoadGraph> route_graph_for(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                                      const map::SiteMap& site);

}  // namespace fleet::robot
