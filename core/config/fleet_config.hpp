#pragma once

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/args.hpp"
#include "config/settings.hpp"
#include "geometry/polygon.hpp"
#include "vehicle/profile.hpp"

namespace fleet::config {

struct RobotSpec {
  std::string id;
  /// Id of a home pose in the site file; empty for a robot declared by count until
  /// assign_homes gives it one.
  std::string home;
  /// A VDA 5050 vehicle's serial number (its MQTT topics' last part); the id when not given.
  std::string serial_number;
};

/// How fleet-vda5050 reaches the vehicles of a fleet of robot type `vda5050`: topics
/// `{interface_name}/v{major}/{manufacturer}/{serial_number}/{topic}`.
struct Vda5050Link {
  std::string interface_name = "uagv";
  std::string version = "2.0.0";  ///< 2.0.0 or 2.1.0
  std::string manufacturer;
};

/// A fleet: robots of one robot type sharing one vehicle profile.
struct FleetSpec {
  std::string id;
  std::string robot_type;  ///< a name of vehicle::robot_types()
  vehicle::VehicleProfile profile;
  /// The profile footprint's extent as a rectangle centred on the body origin: what the
  /// rectangle-based parts (the simulated body, the collision monitor) use.
  geometry::Footprint footprint;
  std::vector<RobotSpec> robots;
  /// Only for robot type `vda5050`.
  std::optional<Vda5050Link> vda5050;
};

struct FleetConfig {
  std::string source;  ///< the file it was read from, for messages
  Settings settings;
  std::vector<FleetSpec> fleets;

  /// Robots of every fleet in declaration order.
  std::vector<std::pair<const FleetSpec*, const RobotSpec*>> all_robots() const;
  /// The fleet a robot belongs to, or nothing.
  std::optional<std::pair<const FleetSpec*, const RobotSpec*>> find_robot(const std::string& robot_id) const;
  /// The speed a fleet's robots drive at: the software's `agent.max_speed`, within what the
  /// fleet's vehicle can do.
  double top_speed(const FleetSpec& fleet) const;

  /// Robot id -> (fleet index, robot index), made by parse_fleet_config: the server looks robots
  /// up for every message, among hundreds. Positions, not pointers, so copies stay right; a
  /// configuration changed after parsing is searched in full.
  std::unordered_map<std::string, std::pair<std::size_t, std::size_t>> robot_index;
};

/// Gives each robot declared by count (`robots: {count: N, id: PATTERN}`, empty home) a home of
/// the site: the site's homes in file order, skipping those a listed robot names. The same
/// configuration and site give every process the same homes. ConfigError when the site has too few.
void assign_homes(FleetConfig& config, const std::vector<std::string>& site_homes, const std::string& site_name);

/// Applies the flags every Fleet process shares to `config`: --domain, --site, --time-scale and
/// --seed override dds.domain, site, time_scale and seed, each checked like the file's value.
void apply_common_flags(Args& args, FleetConfig& config);

/// Applies one `--set KEY=VALUE` to `config`, checked against the schema like the file's value;
/// ArgError naming the text when it is not KEY=VALUE.
void apply_set_flag(FleetConfig& config, const std::string& key_value);

/// Reads fleet.yaml. Throws ConfigError naming the file, line and key for unknown keys, values out
/// of range, duplicate robot ids and malformed YAML.
FleetConfig load_fleet_config(const std::string& path);

/// The same from YAML text; `source` names it in messages.
FleetConfig parse_fleet_config(const std::string& yaml_text, const std::string& source);

}  // namespace fleet::config
