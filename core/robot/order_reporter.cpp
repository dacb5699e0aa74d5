#include "robot/order_reporter.hpp"

namespace fleet::robot {

std::vector<RobotEvent> OrderReporter::take_events() {
  std::vector<RobotEvent> out;
  out.swap(events_);
  return out;
}

void OrderReporter::state_changed(const std::string& order_id, const std::string& state, bool waits) {
  events_.push_back({RobotEvent::Kind::kState, order_id, state, -1, {}});
  if (!waits) detail_.clear();
}

void OrderReporter::phase_changed(const std::string& order_id, orders::OrderPhase phase) {
  if (phase == orders::OrderPhase::kNone) return;
  events_.push_back({RobotEvent::Kind::kPhase, order_id, std::string(orders::to_string(phase)), -1, {}});
}

void OrderReporter::stopped_ahead(const std::string& robot_id) {
  // Naming the robot is what an operator needs to see why this one waits.
  detail_ = robot_id.empty() ? "an obstacle ahead" : "robot " + robot_id + " ahead";
}

void OrderReporter::held_by_traffic(const std::vector<std::string>& blocked_by) {
  if (blocked_by.empty()) {
    detail_ = "waiting for a traffic grant";
    return;
  }
  std::string ids;
  for (const auto& id : blocked_by) ids += (ids.empty() ? "" : ", ") + id;
  detail_ = "waiting for traffic: road held by " + ids;
}

void OrderReporter::driving_on() {
  if (detail_.ends_with(" ahead") || detail_.starts_with("waiting for")) detail_.clear();
}

}  // namespace fleet::robot
