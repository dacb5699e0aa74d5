#pragma once

#include <string>
#include <vector>

#include "orders/order.hpp"
#include "robot/robot.hpp"

namespace fleet::robot {

/// What a robot of any type reports on its order: the events the agent turns into OrderReports
/// and log lines, and the detail text of RobotState (why it waits or failed).
class OrderReporter {
 public:
  void add(RobotEvent event) { events_.push_back(std::move(event)); }
  /// The events since the last call, oldest first.
  std::vector<RobotEvent> take_events();

  const std::string& detail() const { return detail_; }
  void set_detail(std::string text) { detail_ = std::move(text); }

  /// The task state changed to `state`. The detail goes with the state it explained, unless the
  /// robot still `waits` (a wait's detail stays while it lasts).
  void state_changed(const std::string& order_id, const std::string& state, bool waits);
  /// The order's phase changed (nothing for OrderPhase::kNone).
  void phase_changed(const std::string& order_id, orders::OrderPhase phase);

  /// Stopped for something in the way: robot `robot_id`, or an obstacle when the id is empty.
  void stopped_ahead(const std::string& robot_id);
  /// Held at the end of a traffic grant; `blocked_by` are the robots holding the road ahead.
  void held_by_traffic(const std::vector<std::string>& blocked_by);
  /// Driving again: a wait's detail no longer applies.
  void driving_on();

 private:
  std::vector<RobotEvent> events_;
  std::string detail_;
};

}  // namespace fleet::robot
