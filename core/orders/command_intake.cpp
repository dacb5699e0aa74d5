#include "orders/command_intake.hpp"

#include <algorithm>
#include <cstdio>

#include "model/names.hpp"
#include "orders/order_intake.hpp"

namespace fleet::orders {

namespace {

CommandDecision refuse(std::string error) {
  CommandDecision refused;
  refused.error = std::move(error);
  return refused;
}

CommandDecision take(CommandAction action, bool on = false, std::int64_t order_id = 0) {
  CommandDecision taken;
  taken.action = action;
  taken.on = on;
  taken.order_id = order_id;
  return taken;
}

std::vector<std::string> configured_robots(const config::FleetConfig& config) {
  std::vector<std::string> ids;
  for (const auto& [fleet, robot] : config.all_robots()) ids.push_back(robot->id);
  return ids;
}

bool on_or_off(const std::string& value) {
  return value == "on" || value == "off";
}

CommandDecision cancel_order(const model::Command& command, const CommandView& view) {
  std::int64_t id = 0;
  try {
    std::size_t used = 0;
    id = std::stoll(command.target, &used);
    if (used != command.target.size()) throw std::invalid_argument(command.target);
  } catch (const std::exception&) {
    return refuse("order id '" + command.target + "' is not a number");
  }
  const Order* order = view.book.find(id);
  if (!order) return refuse("unknown order " + command.target);
  if (is_final(order->status)) {
    return refuse("order " + command.target + " is already " + std::string(to_string(order->status)));
  }
  return take(CommandAction::kCancelOrder, false, id);
}

CommandDecision switch_obstacle(const model::Command& command, const CommandView& view) {
  const map::StaticObstacle* obstacle = view.site.find_obstacle(command.target);
  if (!obstacle) {
    std::vector<std::string> ids;
    for (const auto& o : view.site.static_obstacles) ids.push_back(o.id);
    return refuse(model::unknown_name_message("obstacle", command.target, ids));
  }
  if (!on_or_off(command.value)) return refuse("obstacle state '" + command.value + "' is not on or off");
  const bool on = command.value == "on";
  if (const std::string robot_id = on ? view.robots.robot_under(obstacle->polygon) : ""; !robot_id.empty()) {
    const auto& pose = view.robots.entries().at(robot_id).last.pose;
    char at[64];
    std::snprintf(at, sizeof at, "(%.2f, %.2f)", pose.x, pose.y);
    std::string error = "obstacle ";
    error += command.target;
    error += " covers robot ";
    error += robot_id;
    error += " at ";
    error += at;
    error += ": switch it on once the robot has left";
    return refuse(std::move(error));
  }
  return take(CommandAction::kSwitchObstacle, on);
}

CommandDecision switch_map(const model::Command& command, const CommandView& view) {
  // [Forklift thesis, section 3]: maps are assigned at the start and whenever the user changes them.
  if (std::find(view.maps.begin(), view.maps.end(), command.value) == view.maps.end()) {
    return refuse(model::unknown_name_message("map", command.value, view.maps));
  }
  const bool one_robot = !command.target.empty() && command.target != "all";
  if (!one_robot) {
    return take(command.value == view.site.name ? CommandAction::kNone : CommandAction::kSwitchMap);
  }
  const std::vector<std::string> robot_ids = configured_robots(view.config);
  if (std::find(robot_ids.begin(), robot_ids.end(), command.target) == robot_ids.end()) {
    return refuse(model::unknown_name_message("robot", command.target, robot_ids));
  }
  if (view.traffic_on) {
    return refuse(
        "traffic control needs every robot on the same map: switch them all (no robot given), or run with "
        "traffic.enabled false");
  }
  return take(CommandAction::kMapOneRobot);
}

CommandDecision pause_robot(const model::Command& command, const CommandView& view) {
  if (!view.config.find_robot(command.target)) {
    return refuse(model::unknown_name_message("robot", command.target, configured_robots(view.config)));
  }
  if (const auto why = why_unseen(command.target, view.robots.registered_ids())) return refuse(*why);
  return take(CommandAction::kPauseRobot, command.verb == "pause");
}

}  // namespace

CommandDecision decide_command(const model::Command& command, const CommandView& view) {
  if (command.verb == "cancel-order") return cancel_order(command, view);
  if (command.verb == "obstacle") return switch_obstacle(command, view);
  if (command.verb == "map") return switch_map(command, view);
  if (command.verb == "auto-orders") {
    if (!on_or_off(command.value)) return refuse("auto-orders value '" + command.value + "' is not on or off");
    return take(CommandAction::kAutoOrders, command.value == "on");
  }
  if (command.verb == "pause" || command.verb == "resume") return pause_robot(command, view);
  return refuse("unknown command '" + command.verb + "' (cancel-order, obstacle, map, auto-orders, pause, resume)");
}

}  // namespace fleet::orders
