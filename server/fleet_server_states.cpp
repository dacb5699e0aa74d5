// The robots' states as they report them: who is registered, lost, back or stalled (RobotRecovery
// decides what becomes of their orders).
#include <cmath>

#include "orders/order_recovery.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

using orders::Order;
using orders::Recovery;

void FleetServer::handle_robot_states() {
  robot_state_reader_.take([&](model::RobotState&& state, const dds::SampleInfo& info) {
    if (!gate_.admit(robot_state_reader_.handle(), info, state.robot_id, "fleet/RobotState")) return;
    if (!info.valid_data) {
      // DDS liveliness: the robot's writer is gone (its 1 s liveliness lease lapsed or it
      // left). Only the key is valid in such a sample.
      auto it = robots_.entries().find(state.robot_id);
      if (!info.alive && it != robots_.entries().end() && it->second.registered && !it->second.lost) {
        recovery_.robot_lost(it->second, "DDS liveliness lost");
      }
      return;
    }
    if (!std::isfinite(state.pose.x) || !std::isfinite(state.pose.y) || !std::isfinite(state.pose.yaw)) {
      gate_.warn(info, "pose",
                 fmt::format("robot {}: ignoring RobotState with a non-finite pose ({}, {}, {})", state.robot_id,
                             state.pose.x, state.pose.y, state.pose.yaw));
      return;
    }
    const auto known = options_.config.find_robot(state.robot_id);
    if (!known) {
      gate_.warn(
          info, "robot",
          fmt::format("ignoring RobotState of robot '{}', which is not in {}", state.robot_id, options_.config.source));
      return;
    }
    RobotEntry& robot = robots_.entries()[state.robot_id];
    if (!robot.registered || robot.lost) {
      log_->info("robot {} ({}) {} at ({:.2f}, {:.2f}), state {}", state.robot_id, known->first->id,
                 robot.lost ? "is back" : "registered", state.pose.x, state.pose.y, state.task_state);
      if (!robot.registered) routing_.open_view_of(state.robot_id);
      // A robot that comes back may still report an order the server has moved on from:
      // tell it so (the latched Order carries the cancellation).
      if (state.order_id != 0) {
        const Order* order = book_.find(state.order_id);
        if (order && orders::when_robot_reappears({.order_final = orders::is_final(order->status),
                                                   .order_is_robots = order->robot_id == state.robot_id}) ==
                         Recovery::kWithdraw) {
          wire_.withdraw(*order, state.robot_id);
        }
      }
    }
    if (robot.lost) recovery_.robot_back(state);
    robot.id = state.robot_id;
    robot.fleet_id = known->first->id;
    robot.registered = true;
    robot.lost = false;
    if (robot.stalled) log_->info("robot {} publishes again after a missed deadline", state.robot_id);
    robot.stalled = false;
    robot.last_seen_wall = SimClock::wall_now();
    robot.last = std::move(state);
    if (traffic_) traffic_->set_body(robot.id, robots_.body_of(robot));
  });
  // DDS deadline on RobotState (0.5 s, dds::qos::robot_state): the robot is stalled — frozen,
  // or its link is — before its lease runs out and it is lost.
  while (const auto missed = robot_state_reader_.deadline_missed()) {
    auto it = robots_.entries().find(missed->robot_id);
    if (it != robots_.entries().end() && it->second.registered && !it->second.lost && !it->second.stalled) {
      it->second.stalled = true;
      log_->warn("robot {} stalled: no RobotState within its 0.5 s DDS deadline", it->first);
    }
  }
}

}  // namespace fleet::server
