#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "vehicle/profile.hpp"

namespace fleet::vehicle {

/// A robot type: software in the agent that drives one kind of vehicle. Its profile defaults come
/// from the vehicle its source document describes; a fleet's profile overrides any of them.
struct RobotType {
  std::string name;
  std::string description;
  /// Every action the software can carry out; a fleet's profile offers a subset.
  std::vector<std::string> possible_actions;
  VehicleProfile defaults;
  /// A place is handled only from a road at least this wide in front of it, metres (a stacker
  /// turns about its rear axle there to reverse in); 0: any road the vehicle fits.
  double handling_road_width = 0.0;
  /// False for vehicles that run software of their own and are driven over VDA 5050 by
  /// fleet-vda5050: no agent is started for them.
  bool agent_driven = true;
};

/// The robot types: those the agent can build, then `vda5050`, in a stable order.
const std::vector<RobotType>& robot_types();
const RobotType* find_robot_type(std::string_view name);
/// "forklift, ..." for messages.
std::string robot_type_names();

/// Actions every order may use whatever the fleet: none today (a `move` order has no action).
bool is_known_action(std::string_view action);
/// Every action name some robot type can perform, for messages and checks.
std::vector<std::string> known_actions();

}  // namespace fleet::vehicle
