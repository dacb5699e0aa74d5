// What the server does when robots are lost, come back, restart or do not acknowledge: it asks
// orders::order_recovery for the decision and carries it out.
#include <cmath>

#include "monitor/robot_health.hpp"
#include "orders/order_recovery.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderStatus;
using orders::Recovery;
using orders::TransitionResult;

void FleetServer::handle_robot_states() {
  robot_state_reader_.take([&](model::RobotState&& state, const dds::SampleInfo& info) {
    if (!gate_.admit(robot_state_reader_.handle(), info, state.robot_id, "fleet/RobotState")) return;
    if (!info.valid_data) {
      // DDS liveliness: the robot's writer is gone (its 1 s liveliness lease lapsed or it
      // left). Only the key is valid in such a sample.
      auto it = robots_.entries().find(state.robot_id);
      if (!info.alive && it != robots_.entries().end() && it->second.registered && !it->second.lost) {
        robot_lost(it->second, "DDS liveliness lost");
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
          withdraw(*order, state.robot_id);
        }
      }
    }
    if (robot.lost) resume_or_fail_waiting_orders(state);
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
}

void FleetServer::robot_lost(RobotEntry& robot, const std::string& why) {
  robot.lost = true;
  log_->warn("robot {} lost: {}", robot.id, why);
  // Where its body was last seen stays blocked: a dead robot is still in the way.
  if (traffic_) traffic_->robot_lost(robot.id, robots_.body_of(robot), clock_.now());
  if (const Order* order = book_.open_order_of(robot.id)) {
    const std::int64_t id = order->id;
    const bool boxes = orders::boxes_aboard(*order);
    if (orders::when_robot_lost({order->phase, robot.last.carrying_pallet, boxes}) == Recovery::kWait) {
      recovery_.wait_for_lost_robot(id, SimClock::wall_now());
      log_->warn("order {} waits for robot {}: lost {} (at most {:.0f} s)", id, robot.id,
                 robot.last.carrying_pallet ? "with the pallet on its forks"
                 : boxes                    ? "with the tour's boxes on its tray"
                                            : "at the pick area",
                 options_.config.settings.get_double("server.lost_with_pallet_wait_s"));
      return;
    }
    requeue_taken_from(id, robot.id, "robot " + robot.id + " lost");
  }
}

void FleetServer::requeue_taken_from(std::int64_t order_id, const std::string& robot_id, const std::string& reason) {
  if (book_.requeue(order_id, clock_.now(), reason) != TransitionResult::kApplied) return;
  log_->warn("order {} re-queued: {}", order_id, reason);
  recovery_.settled(order_id);
  publish_order(*book_.find(order_id));
  withdraw(*book_.find(order_id), robot_id);
}

bool FleetServer::hand_back(const Order& order, const model::OrderReport& report) {
  const std::int64_t id = order.id;
  const std::string holder = order.robot_id;
  const double now = clock_.now();
  if (order.status != OrderStatus::kQueued) {
    if (book_.requeue(id, now, "handed back to " + report.robot_id + ", which has the pallet") !=
        TransitionResult::kApplied) {
      return false;
    }
    withdraw(*book_.find(id), holder);
  }
  if (book_.assign(id, report.robot_id, now) != TransitionResult::kApplied) return false;
  const Order& handed = *book_.find(id);
  log_->warn("order {} handed back to {}: it lifted the pallet at {} before the order's withdrawal reached it{}", id,
             report.robot_id, handed.pick_area, holder.empty() ? "" : " (taken from " + holder + ")");
  recovery_.handed_back(id);
  publish_order(handed);
  send_assignment(handed);
  return true;
}

void FleetServer::fail_with_pallet(std::int64_t order_id, const std::string& reason) {
  if (book_.transition(order_id, OrderStatus::kFailed, clock_.now(), reason) != TransitionResult::kApplied) return;
  log_->warn("order {} failed: {}", order_id, reason);
  recovery_.settled(order_id);
  publish_order(*book_.find(order_id));
}

void FleetServer::give_up_on_lost_robot(std::int64_t order_id, Recovery decision, const std::string& why,
                                        const std::string& failure) {
  const Order* order = book_.find(order_id);
  if (!order) return;
  const std::string robot_id = order->robot_id;
  if (decision == Recovery::kRequeue) {
    // Lost at the pick area before the lift: the pallet still stands there.
    requeue_taken_from(order_id, robot_id, why + " before lifting the pallet");
    return;
  }
  const std::string pick_area = order->pick_area;
  fail_with_pallet(order_id, failure);
  site_keeper_.return_pallet_of(robot_id, pick_area);
}

void FleetServer::resume_or_fail_waiting_orders(const model::RobotState& state) {
  const orders::ReturningRobot robot{state.robot_id, state.order_id, state.carrying_pallet};
  for (const orders::RecoveryStep& step : recovery_.robot_back(robot, book_, site_keeper_.state().ledger)) {
    if (step.action == Recovery::kKeep) {
      log_->info("order {} resumes: robot {} is back with it ({})", step.order_id, state.robot_id,
                 state.carrying_pallet                                     ? "pallet on its forks"
                 : orders::at_pick_place(book_.find(step.order_id)->phase) ? "still at the pick area"
                                                                           : "pallet put down at the drop area");
      continue;
    }
    give_up_on_lost_robot(step.order_id, step.action, "robot " + state.robot_id + " came back restarted",
                          "robot " + state.robot_id + " came back without the order's pallet (restarted)");
    if (step.withdraw) withdraw(*book_.find(step.order_id), state.robot_id);
  }
}

void FleetServer::check_robot_health() {
  const double now = SimClock::wall_now();
  const double lost_after = options_.config.settings.get_double("server.robot_lost_after_s");
  // DDS deadline on RobotState (0.5 s, dds::qos::robot_state): the robot is stalled — frozen,
  // or its link is — before its lease runs out and it is lost.
  while (const auto missed = robot_state_reader_.deadline_missed()) {
    auto it = robots_.entries().find(missed->robot_id);
    if (it != robots_.entries().end() && it->second.registered && !it->second.lost && !it->second.stalled) {
      it->second.stalled = true;
      log_->warn("robot {} stalled: no RobotState within its 0.5 s DDS deadline", it->first);
    }
  }
  for (auto& [id, robot] : robots_.entries()) {
    if (robot.registered && !robot.lost && monitor::silent_too_long(now - robot.last_seen_wall, lost_after)) {
      robot_lost(robot, "no RobotState for " + std::to_string(now - robot.last_seen_wall).substr(0, 4) + " s");
    }
  }
  check_orders_waiting_for_lost_robots(now);
  if (now - started_wall_ > orders::restart_grace_s(lost_after)) check_restored_orders();
  if (body_memory_.due(now)) {
    std::map<std::string, geometry::Pose2> heard;
    for (const auto& [id, robot] : robots_.entries()) {
      if (robot.registered && !robot.lost) heard[id] = robot.last.pose;
    }
    body_memory_.remember(heard, now);
  }
}

void FleetServer::check_orders_waiting_for_lost_robots(double now_wall) {
  const double pallet_wait = options_.config.settings.get_double("server.lost_with_pallet_wait_s");
  const std::string waited = std::to_string(static_cast<int>(pallet_wait)) + " s";
  for (const orders::RecoveryStep& step :
       recovery_.check_waiting(now_wall, pallet_wait, book_, site_keeper_.state().ledger)) {
    give_up_on_lost_robot(step.order_id, step.action, "robot " + step.robot_id + " lost for " + waited,
                          "robot " + step.robot_id + " lost with the pallet for " + waited);
  }
}

void FleetServer::check_restored_orders() {
  // Orders restored from the database whose robot has not shown up since the restart: after a
  // grace period the robot counts as lost, with the load on board when the order was past the lift.
  for (const auto& [order_id, order] : book_.all()) {
    if (orders::is_final(order.status) || order.status == OrderStatus::kQueued) continue;
    if (robots_.entries().contains(order.robot_id)) continue;
    RobotEntry& ghost = robots_.entries()[order.robot_id];
    ghost.id = order.robot_id;
    ghost.registered = false;
    ghost.last.carrying_pallet = orders::restored_robot_carried_load(order.phase);
    // Its body stays held where it last stood (hold_unheard_robots), not at the map's origin.
    if (const auto stood = body_memory_.before_start().find(order.robot_id);
        stood != body_memory_.before_start().end()) {
      ghost.last.pose = stood->second;
    }
    robot_lost(ghost, "not seen since the server restarted");
    break;  // book_ changed; the next pass handles the rest
  }
}

void FleetServer::check_acknowledgements() {
  const double timeout = options_.config.settings.get_double("server.order_ack_timeout_s");
  const long limit = options_.config.settings.get_int("server.order_resend_limit");
  const auto steps = recovery_.check_acknowledgements(SimClock::wall_now(), timeout, limit, book_);
  for (const orders::RecoveryStep& step : steps) {
    const Order& order = *book_.find(step.order_id);
    if (step.action == Recovery::kResend) {
      log_->warn("order {} not acknowledged by {} within {} s; re-sending ({}/{})", step.order_id, step.robot_id,
                 timeout, step.resends, limit);
      send_assignment(order);
      continue;
    }
    book_.requeue(step.order_id, clock_.now(), "not acknowledged by " + step.robot_id);
    log_->warn("order {} re-queued: never acknowledged by {}", step.order_id, step.robot_id);
    publish_order(order);
    withdraw(order, step.robot_id);
  }
}

}  // namespace fleet::server
