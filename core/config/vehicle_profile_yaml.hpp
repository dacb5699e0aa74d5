#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "vehicle/vehicle_types.hpp"

namespace fleet::config {

/// A fleet's `profile:` map over its robot type's defaults; absent keys keep the default. Throws
/// ConfigError naming the file, line and key: unknown keys, a footprint that is not a simple
/// polygon, an unknown kinematics, an action the robot type cannot perform.
vehicle::VehicleProfile parse_vehicle_profile(const YAML::Node& node, const vehicle::RobotType& type,
                                              const std::string& key, const std::string& source);

}  // namespace fleet::config
