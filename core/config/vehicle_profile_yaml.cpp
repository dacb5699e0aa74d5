#include "config/vehicle_profile_yaml.hpp"

#include <algorithm>

#include "config/settings.hpp"
#include "config/yaml_checks.hpp"

namespace fleet::config {

namespace {

using yaml::where;

/// `{length: L, width: W}` (a rectangle centred on the body origin) or a list of [x, y] corners.
geometry::Polygon parse_footprint(const YAML::Node& node, const std::string& key, const std::string& source) {
  if (node.IsMap()) {
    yaml::check_keys(node, {"length", "width"}, key, source);
    return vehicle::rectangle(yaml::positive_number(node["length"], key + ".length", source),
                              yaml::positive_number(node["width"], key + ".width", source));
  }
  if (!node.IsSequence()) {
    throw ConfigError(where(source, node) + ": key '" + key +
                      "' must be {length, width} or a list of [x, y] corners in metres");
  }
  geometry::Polygon polygon;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node corner = node[i];
    const std::string ckey = key + "[" + std::to_string(i) + "]";
    if (!corner.IsSequence() || corner.size() != 2) {
      throw ConfigError(where(source, corner) + ": key '" + ckey + "' must be a corner [x, y] in metres");
    }
    geometry::Vec2 p;
    for (std::size_t axis = 0; axis < 2; ++axis) {
      try {
        (axis == 0 ? p.x : p.y) = corner[axis].as<double>();
      } catch (const YAML::Exception&) {
        throw ConfigError(where(source, corner) + ": key '" + ckey + "': '" + corner[axis].Scalar() +
                          "' is not a number");
      }
    }
    polygon.push_back(p);
  }
  if (!vehicle::is_simple_polygon(polygon)) {
    throw ConfigError(where(source, node) + ": key '" + key +
                      "' is not a simple polygon (at least 3 distinct corners, no crossing edges, non-zero area)");
  }
  // Counter-clockwise, as every polygon in Fleet.
  if (geometry::signed_area(polygon) < 0.0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

void parse_kinematics(const YAML::Node& node, vehicle::VehicleProfile& profile, const std::string& key,
                      const std::string& source) {
  const YAML::Node type_node = node.IsMap() ? node["type"] : node;
  if (!type_node || !type_node.IsScalar()) {
    throw ConfigError(where(source, node) + ": key '" + key + "' must be omni, differential or {type: tricycle, ...}");
  }
  const auto kinematics = vehicle::parse_kinematics(type_node.Scalar());
  if (!kinematics) {
    throw ConfigError(where(source, type_node) + ": key '" + key + "': '" + type_node.Scalar() +
                      "' is not a kinematics (omni, differential, tricycle)");
  }
  profile.kinematics = *kinematics;
  if (node.IsMap()) {
    yaml::check_keys(node, {"type", "wheelbase", "max_steering_angle", "rear_axle_x"}, key, source);
    if (node["wheelbase"]) profile.wheelbase = yaml::positive_number(node["wheelbase"], key + ".wheelbase", source);
    if (node["max_steering_angle"]) {
      profile.max_steering_angle =
          yaml::positive_number(node["max_steering_angle"], key + ".max_steering_angle", source);
    }
    if (node["rear_axle_x"])
      profile.rear_axle_x = yaml::finite_number(node["rear_axle_x"], key + ".rear_axle_x", source);
  }
}

void parse_load(const YAML::Node& node, vehicle::LoadHandling& load, const std::string& key,
                const std::string& source) {
  if (!node.IsMap()) throw ConfigError(where(source, node) + ": key '" + key + "' must be a map");
  yaml::check_keys(node, {"type", "max_mass", "lift_height"}, key, source);
  if (node["type"]) {
    load.load_type = node["type"].Scalar();
    if (load.load_type != "pallet" && load.load_type != "box" && load.load_type != "none") {
      throw ConfigError(where(source, node["type"]) + ": key '" + key + ".type': '" + load.load_type +
                        "' is not a load type (pallet, box, none)");
    }
  }
  if (node["max_mass"]) load.max_mass = yaml::non_negative_number(node["max_mass"], key + ".max_mass", source);
  if (node["lift_height"]) {
    load.lift_height = yaml::non_negative_number(node["lift_height"], key + ".lift_height", source);
  }
}

std::vector<std::string> parse_actions(const YAML::Node& node, const vehicle::RobotType& type, const std::string& key,
                                       const std::string& source) {
  if (!node.IsSequence()) throw ConfigError(where(source, node) + ": key '" + key + "' must be a list");
  std::vector<std::string> actions;
  for (const auto& item : node) {
    const std::string action = item.Scalar();
    const auto& possible = type.possible_actions;
    if (std::find(possible.begin(), possible.end(), action) == possible.end()) {
      std::string list;
      for (const auto& a : possible) list += (list.empty() ? "" : ", ") + a;
      throw ConfigError(where(source, item) + ": key '" + key + "': a " + type.name + " cannot perform '" + action +
                        "' (it can: " + list + ")");
    }
    if (std::find(actions.begin(), actions.end(), action) == actions.end()) actions.push_back(action);
  }
  return actions;
}

}  // namespace

vehicle::VehicleProfile parse_vehicle_profile(const YAML::Node& node, const vehicle::RobotType& type,
                                              const std::string& key, const std::string& source) {
  vehicle::VehicleProfile profile = type.defaults;
  if (!node) return profile;
  if (!node.IsMap()) throw ConfigError(where(source, node) + ": key '" + key + "' must be a map");
  yaml::check_keys(node,
                   {"footprint", "kinematics", "max_speed", "max_acceleration", "max_yaw_rate", "load", "actions"}, key,
                   source);
  if (node["footprint"]) profile.footprint = parse_footprint(node["footprint"], key + ".footprint", source);
  if (node["kinematics"]) parse_kinematics(node["kinematics"], profile, key + ".kinematics", source);
  for (const auto& [name, field] : {std::pair{"max_speed", &vehicle::VehicleProfile::max_speed},
                                    std::pair{"max_acceleration", &vehicle::VehicleProfile::max_acceleration},
                                    std::pair{"max_yaw_rate", &vehicle::VehicleProfile::max_yaw_rate}}) {
    if (node[name]) profile.*field = yaml::positive_number(node[name], key + "." + name, source);
  }
  if (node["load"]) parse_load(node["load"], profile.load, key + ".load", source);
  if (node["actions"]) profile.actions = parse_actions(node["actions"], type, key + ".actions", source);
  if (auto error = vehicle::profile_error(profile)) {
    throw ConfigError(where(source, node) + ": key '" + key + "." + error->key + "': " + error->message);
  }
  return profile;
}

}  // namespace fleet::config
