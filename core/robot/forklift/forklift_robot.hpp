#pragma once

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "robot/forklift/forklift.hpp"
#include "robot/robot_factory.hpp"

namespace fleet::robot {

/// The forklift software's settings for a robot of `fleet` on `site`: sized to the fleet's vehicle
/// profile, at its top speed, with the margins traffic leaves (see lookahead_gap). Other types
/// that drive the forklift software (the picker's base) start from it.
ForkliftConfig forklift_robot_config(const config::FleetConfig& config, const config::FleetSpec& fleet,
                                     const map::SiteMap& site);

}  // namespace fleet::robot
