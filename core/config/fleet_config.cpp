#include "config/fleet_config.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "config/vehicle_profile_yaml.hpp"
#include "config/yaml_checks.hpp"

namespace fleet::config {

namespace {

using yaml::check_keys;
using yaml::positive_number;
using yaml::required_text;
using yaml::where;

void flatten(const YAML::Node& node, const std::string& prefix, const std::string& source, Settings& settings) {
  for (const auto& item : node) {
    const std::string key = prefix.empty() ? item.first.as<std::string>() : prefix + "." + item.first.as<std::string>();
    if (item.second.IsMap()) {
      flatten(item.second, key, source, settings);
    } else if (item.second.IsScalar()) {
      settings.set(key, item.second.Scalar(), where(source, item.second));
    } else {
      throw ConfigError(where(source, item.second) + ": key '" + key + "' must be a single value");
    }
  }
}

constexpr int kMaxCountedRobots = 10000;

void add_robot(RobotSpec robot, const YAML::Node& node, const std::string& key, const std::string& source,
               FleetSpec& fleet, std::set<std::string>& robot_ids) {
  if (fleet.vda5050 && robot.serial_number.empty()) robot.serial_number = robot.id;
  if (!robot_ids.insert(robot.id).second) {
    throw ConfigError(where(source, node) + ": key '" + key + ".id': duplicate robot id '" + robot.id + "'");
  }
  fleet.robots.push_back(std::move(robot));
}

/// `robots:` is a list of {id, home}, or {count: N, id: PATTERN}: N robots named by PATTERN with
/// `{n}` replaced by 1..N, their homes given later from the site's free homes (assign_homes).
void parse_robots(const YAML::Node& robots, const YAML::Node& fleet_node, const std::string& fleet_key,
                  const std::string& source, FleetSpec& fleet, std::set<std::string>& robot_ids) {
  const std::string key = fleet_key + ".robots";
  if (robots && robots.IsMap()) {
    check_keys(robots, {"count", "id"}, key, source);
    const double count = positive_number(robots["count"], key + ".count", source);
    if (count != std::floor(count) || count > kMaxCountedRobots) {
      throw ConfigError(where(source, robots["count"]) + ": key '" + key + ".count' must be a whole number 1 .. " +
                        std::to_string(kMaxCountedRobots));
    }
    const std::string pattern = required_text(robots, "id", key, source);
    const auto slot = pattern.find("{n}");
    if (slot == std::string::npos) {
      throw ConfigError(where(source, robots["id"]) + ": key '" + key + ".id': '" + pattern +
                        "' must hold {n}, the robot's number (e.g. fl{n})");
    }
    for (int n = 1; n <= static_cast<int>(count); ++n) {
      std::string id = pattern;
      id.replace(slot, 3, std::to_string(n));
      add_robot({std::move(id), "", ""}, robots, key, source, fleet, robot_ids);
    }
    return;
  }
  if (!robots || !robots.IsSequence() || robots.size() == 0) {
    throw ConfigError(where(source, fleet_node) + ": key '" + key +
                      "' must be a non-empty list, or {count: N, id: PATTERN}");
  }
  for (std::size_t j = 0; j < robots.size(); ++j) {
    const std::string rkey = key + "[" + std::to_string(j) + "]";
    const YAML::Node r = robots[j];
    if (!r.IsMap()) throw ConfigError(where(source, r) + ": key '" + rkey + "' must be a map");
    check_keys(r, {"id", "home", "serial_number"}, rkey, source);
    RobotSpec robot{required_text(r, "id", rkey, source), required_text(r, "home", rkey, source), ""};
    if (r["serial_number"]) {
      if (!fleet.vda5050) {
        throw ConfigError(where(source, r["serial_number"]) + ": key '" + rkey +
                          ".serial_number' is only for robot type vda5050");
      }
      robot.serial_number = required_text(r, "serial_number", rkey, source);
    }
    add_robot(std::move(robot), r, rkey, source, fleet, robot_ids);
  }
}

/// `vda5050: {manufacturer, interface_name, version}` of a fleet of robot type vda5050.
Vda5050Link parse_vda5050_link(const YAML::Node& node, const YAML::Node& fleet_node, const std::string& key,
                               const std::string& source) {
  if (!node || !node.IsMap()) {
    throw ConfigError(where(source, node ? node : fleet_node) + ": key '" + key +
                      "' must be a map {manufacturer, interface_name, version} for robot type vda5050");
  }
  check_keys(node, {"manufacturer", "interface_name", "version"}, key, source);
  Vda5050Link link;
  link.manufacturer = required_text(node, "manufacturer", key, source);
  if (node["interface_name"]) link.interface_name = required_text(node, "interface_name", key, source);
  if (node["version"]) link.version = required_text(node, "version", key, source);
  if (link.version != "2.0.0" && link.version != "2.1.0") {
    throw ConfigError(where(source, node["version"]) + ": key '" + key + ".version': '" + link.version +
                      "' is not a VDA 5050 version Fleet speaks (2.0.0, 2.1.0)");
  }
  for (const std::string* part : {&link.manufacturer, &link.interface_name}) {
    if (part->find_first_of("/+#") != std::string::npos) {
      throw ConfigError(where(source, node) + ": key '" + key + "': '" + *part +
                        "' holds a character MQTT topics reserve (/, + or #)");
    }
  }
  return link;
}

std::vector<FleetSpec> parse_fleets(const YAML::Node& node, const std::string& source) {
  if (!node.IsSequence()) throw ConfigError(where(source, node) + ": key 'fleets' must be a list");
  std::vector<FleetSpec> fleets;
  std::set<std::string> fleet_ids, robot_ids;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node f = node[i];
    const std::string key = "fleets[" + std::to_string(i) + "]";
    if (!f.IsMap()) throw ConfigError(where(source, f) + ": key '" + key + "' must be a map");
    if (f["footprint"]) {
      throw ConfigError(where(source, f["footprint"]) + ": key '" + key +
                        ".footprint' belongs in the vehicle profile: '" + key + ".profile.footprint'");
    }
    check_keys(f, {"id", "robot_type", "profile", "robots", "vda5050"}, key, source);
    FleetSpec fleet;
    fleet.id = required_text(f, "id", key, source);
    fleet.robot_type = required_text(f, "robot_type", key, source);
    const vehicle::RobotType* type = vehicle::find_robot_type(fleet.robot_type);
    if (type == nullptr) {
      throw ConfigError(where(source, f["robot_type"]) + ": key '" + key + ".robot_type': '" + fleet.robot_type +
                        "' is not a known robot type (" + vehicle::robot_type_names() + ")");
    }
    if (!fleet_ids.insert(fleet.id).second) {
      throw ConfigError(where(source, f) + ": key '" + key + ".id': duplicate fleet id '" + fleet.id + "'");
    }
    if (!type->agent_driven) {
      fleet.vda5050 = parse_vda5050_link(f["vda5050"], f, key + ".vda5050", source);
    } else if (f["vda5050"]) {
      throw ConfigError(where(source, f["vda5050"]) + ": key '" + key + ".vda5050' is only for robot type vda5050");
    }
    fleet.profile = parse_vehicle_profile(f["profile"], *type, key + ".profile", source);
    fleet.footprint = fleet.profile.extent();
    parse_robots(f["robots"], f, key, source, fleet, robot_ids);
    fleets.push_back(std::move(fleet));
  }
  return fleets;
}

}  // namespace

std::vector<std::pair<const FleetSpec*, const RobotSpec*>> FleetConfig::all_robots() const {
  std::vector<std::pair<const FleetSpec*, const RobotSpec*>> out;
  for (const FleetSpec& f : fleets) {
    for (const RobotSpec& r : f.robots) out.emplace_back(&f, &r);
  }
  return out;
}

std::optional<std::pair<const FleetSpec*, const RobotSpec*>> FleetConfig::find_robot(
    const std::string& robot_id) const {
  if (const auto it = robot_index.find(robot_id); it != robot_index.end()) {
    const auto [f, r] = it->second;
    if (f < fleets.size() && r < fleets[f].robots.size() && fleets[f].robots[r].id == robot_id) {
      return std::pair{&fleets[f], &fleets[f].robots[r]};
    }
  }
  for (const FleetSpec& f : fleets) {
    for (const RobotSpec& r : f.robots) {
      if (r.id == robot_id) return std::pair{&f, &r};
    }
  }
  return std::nullopt;
}

double FleetConfig::top_speed(const FleetSpec& fleet) const {
  return std::min(settings.get_double("agent.max_speed"), fleet.profile.max_speed);
}

void assign_homes(FleetConfig& config, const std::vector<std::string>& site_homes, const std::string& site_name) {
  std::set<std::string> taken;
  std::size_t wanted = 0;
  for (const FleetSpec& fleet : config.fleets) {
    for (const RobotSpec& robot : fleet.robots) {
      if (robot.home.empty())
        ++wanted;
      else
        taken.insert(robot.home);
    }
  }
  std::vector<std::string> free;
  for (const std::string& home : site_homes) {
    if (!taken.contains(home)) free.push_back(home);
  }
  if (wanted > free.size()) {
    throw ConfigError(config.source + ": the fleets declare " + std::to_string(wanted) +
                      " robots by count, but site '" + site_name + "' has " + std::to_string(free.size()) +
                      " homes left for them (" + std::to_string(site_homes.size()) + " in all)");
  }
  std::size_t next = 0;
  for (FleetSpec& fleet : config.fleets) {
    for (RobotSpec& robot : fleet.robots) {
      if (robot.home.empty()) robot.home = free[next++];
    }
  }
}

void apply_common_flags(Args& args, FleetConfig& config) {
  // A container or a service unit names its security folder once for every binary it runs; the
  // flag still wins over it.
  if (const char* folder = std::getenv("FLEET_SECURITY"); folder != nullptr && *folder != '\0') {
    config.settings.set("dds.security", folder, "FLEET_SECURITY");
  }
  for (const auto& [flag, key] :
       {std::pair{"domain", "dds.domain"}, std::pair{"site", "site"}, std::pair{"time-scale", "time_scale"},
        std::pair{"seed", "seed"}, std::pair{"security", "dds.security"}}) {
    if (auto v = args.value(flag)) config.settings.set(key, *v, std::string("--") + flag);
  }
  // --set KEY=VALUE, repeatable: any configuration key, checked against the schema like the file.
  while (auto v = args.value("set")) apply_set_flag(config, *v);
}

void apply_set_flag(FleetConfig& config, const std::string& key_value) {
  const auto eq = key_value.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw ArgError("--set '" + key_value + "': expected KEY=VALUE, e.g. traffic.enabled=false");
  }
  config.settings.set(key_value.substr(0, eq), key_value.substr(eq + 1), "--set");
}

FleetConfig parse_fleet_config(const std::string& yaml_text, const std::string& source) {
  FleetConfig config;
  config.source = source;
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(source + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
  if (!root.IsMap()) throw ConfigError(source + ": expected a map of keys at the top level");
  for (const auto& item : root) {
    const std::string key = item.first.as<std::string>();
    if (key == "fleets") {
      config.fleets = parse_fleets(item.second, source);
    } else if (item.second.IsMap()) {
      flatten(item.second, key, source, config.settings);
    } else if (item.second.IsScalar()) {
      config.settings.set(key, item.second.Scalar(), where(source, item.second));
    } else {
      throw ConfigError(where(source, item.second) + ": key '" + key + "' must be a single value");
    }
  }
  if (config.fleets.empty()) throw ConfigError(source + ": key 'fleets' is missing: declare at least one fleet");
  for (std::size_t f = 0; f < config.fleets.size(); ++f) {
    for (std::size_t r = 0; r < config.fleets[f].robots.size(); ++r)
      config.robot_index[config.fleets[f].robots[r].id] = {f, r};
  }
  return config;
}

FleetConfig load_fleet_config(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ConfigError(path + ": cannot open the configuration file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_fleet_config(buffer.str(), path);
}

}  // namespace fleet::config
