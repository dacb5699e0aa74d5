#include "server/robot_recovery.hpp"

#include <map>

#include "monitor/robot_health.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderStatus;
using orders::Recovery;
using orders::TransitionResult;

void RobotRecovery::robot_lost(orders::RobotEntry& robot, const std::string& why) {
  robot.lost = true;
  p_.log->warn("robot {} lost: {}", robot.id, why);
  // Where its body was last seen stays blocked: a dead robot is still in the way.
  if (p_.traffic) p_.traffic->robot_lost(robot.id, p_.robots.body_of(robot), p_.clock.now());
  if (const Order* order = p_.book.open_order_of(robot.id)) {
    const std::int64_t id = order->id;
    const bool boxes = orders::boxes_aboard(*order);
    if (orders::when_robot_lost({order->phase, robot.last.carrying_pallet, boxes}) == Recovery::kWait) {
      p_.watch.wait_for_lost_robot(id, SimClock::wall_now());
      p_.log->warn("order {} waits for robot {}: lost {} (at most {:.0f} s)", id, robot.id,
                   robot.last.carrying_pallet ? "with the pallet on its forks"
                   : boxes                    ? "with the tour's boxes on its tray"
                                              : "at the pick area",
                   p_.config.settings.get_double("server.lost_with_pallet_wait_s"));
      return;
    }
    requeue_taken_from(id, robot.id, "robot " + robot.id + " lost");
  }
}

void RobotRecovery::requeue_taken_from(std::int64_t order_id, const std::string& robot_id, const std::string& reason) {
  if (p_.book.requeue(order_id, p_.clock.now(), reason) != TransitionResult::kApplied) return;
  p_.log->warn("order {} re-queued: {}", order_id, reason);
  p_.watch.settled(order_id);
  p_.wire.publish(*p_.book.find(order_id));
  p_.wire.withdraw(*p_.book.find(order_id), robot_id);
}

bool RobotRecovery::hand_back(const Order& order, const model::OrderReport& report) {
  const std::int64_t id = order.id;
  const std::string holder = order.robot_id;
  const double now = p_.clock.now();
  if (order.status != OrderStatus::kQueued) {
    if (p_.book.requeue(id, now, "handed back to " + report.robot_id + ", which has the pallet") !=
        TransitionResult::kApplied) {
      return false;
    }
    p_.wire.withdraw(*p_.book.find(id), holder);
  }
  if (p_.book.assign(id, report.robot_id, now) != TransitionResult::kApplied) return false;
  const Order& handed = *p_.book.find(id);
  p_.log->warn("order {} handed back to {}: it lifted the pallet at {} before the order's withdrawal reached it{}", id,
               report.robot_id, handed.pick_area, holder.empty() ? "" : " (taken from " + holder + ")");
  p_.watch.handed_back(id);
  p_.wire.publish(handed);
  p_.wire.assign(handed);
  return true;
}

void RobotRecovery::fail_with_pallet(std::int64_t order_id, const std::string& reason) {
  if (p_.book.transition(order_id, OrderStatus::kFailed, p_.clock.now(), reason) != TransitionResult::kApplied) {
    return;
  }
  p_.log->warn("order {} failed: {}", order_id, reason);
  p_.watch.settled(order_id);
  p_.wire.publish(*p_.book.find(order_id));
}

void RobotRecovery::give_up_on_lost_robot(std::int64_t order_id, Recovery decision, const std::string& why,
                                          const std::string& failure) {
  const Order* order = p_.book.find(order_id);
  if (!order) return;
  const std::string robot_id = order->robot_id;
  if (decision == Recovery::kRequeue) {
    // Lost at the pick area before the lift: the pallet still stands there.
    requeue_taken_from(order_id, robot_id, why + " before lifting the pallet");
    return;
  }
  const std::string pick_area = order->pick_area;
  fail_with_pallet(order_id, failure);
  p_.site_keeper.return_pallet_of(robot_id, pick_area);
}

void RobotRecovery::robot_back(const model::RobotState& state) {
  const orders::ReturningRobot robot{state.robot_id, state.order_id, state.carrying_pallet};
  for (const orders::RecoveryStep& step : p_.watch.robot_back(robot, p_.book, p_.site_keeper.state().ledger)) {
    if (step.action == Recovery::kKeep) {
      p_.log->info("order {} resumes: robot {} is back with it ({})", step.order_id, state.robot_id,
                   state.carrying_pallet                                       ? "pallet on its forks"
                   : orders::at_pick_place(p_.book.find(step.order_id)->phase) ? "still at the pick area"
                                                                               : "pallet put down at the drop area");
      continue;
    }
    give_up_on_lost_robot(step.order_id, step.action, "robot " + state.robot_id + " came back restarted",
                          "robot " + state.robot_id + " came back without the order's pallet (restarted)");
    if (step.withdraw) p_.wire.withdraw(*p_.book.find(step.order_id), state.robot_id);
  }
}

void RobotRecovery::hold_unheard_robots() {
  if (!p_.traffic) return;
  for (const auto& [id, pose] : p_.body_memory.before_start()) {
    if (!p_.config.find_robot(id)) continue;
    orders::RobotEntry unheard;
    unheard.id = id;
    unheard.last.pose = pose;
    p_.traffic->set_body(id, p_.robots.body_of(unheard));
    p_.log->info("robot {} not heard from yet: its body is held where it last stood ({:.2f}, {:.2f})", id, pose.x,
                 pose.y);
  }
}

void RobotRecovery::check(double now_wall, double started_wall) {
  const double lost_after = p_.config.settings.get_double("server.robot_lost_after_s");
  for (auto& [id, robot] : p_.robots.entries()) {
    if (robot.registered && !robot.lost && monitor::silent_too_long(now_wall - robot.last_seen_wall, lost_after)) {
      robot_lost(robot, "no RobotState for " + std::to_string(now_wall - robot.last_seen_wall).substr(0, 4) + " s");
    }
  }
  check_orders_waiting_for_lost_robots(now_wall);
  if (now_wall - started_wall > orders::restart_grace_s(lost_after)) check_restored_orders();
  if (p_.body_memory.due(now_wall)) {
    std::map<std::string, geometry::Pose2> heard;
    for (const auto& [id, robot] : p_.robots.entries()) {
      if (robot.registered && !robot.lost) heard[id] = robot.last.pose;
    }
    p_.body_memory.remember(heard, now_wall);
  }
}

void RobotRecovery::check_orders_waiting_for_lost_robots(double now_wall) {
  const double pallet_wait = p_.config.settings.get_double("server.lost_with_pallet_wait_s");
  const std::string waited = std::to_string(static_cast<int>(pallet_wait)) + " s";
  for (const orders::RecoveryStep& step :
       p_.watch.check_waiting(now_wall, pallet_wait, p_.book, p_.site_keeper.state().ledger)) {
    give_up_on_lost_robot(step.order_id, step.action, "robot " + step.robot_id + " lost for " + waited,
                          "robot " + step.robot_id + " lost with the pallet for " + waited);
  }
}

void RobotRecovery::check_restored_orders() {
  // Orders restored from the database whose robot has not shown up since the restart: after a
  // grace period the robot counts as lost, with the load on board when the order was past the lift.
  for (const auto& [order_id, order] : p_.book.all()) {
    if (orders::is_final(order.status) || order.status == OrderStatus::kQueued) continue;
    if (p_.robots.entries().contains(order.robot_id)) continue;
    orders::RobotEntry& ghost = p_.robots.entries()[order.robot_id];
    ghost.id = order.robot_id;
    ghost.registered = false;
    ghost.last.carrying_pallet = orders::restored_robot_carried_load(order.phase);
    // Its body stays held where it last stood (hold_unheard_robots), not at the map's origin.
    if (const auto stood = p_.body_memory.before_start().find(order.robot_id);
        stood != p_.body_memory.before_start().end()) {
      ghost.last.pose = stood->second;
    }
    robot_lost(ghost, "not seen since the server restarted");
    break;  // the book changed; the next pass handles the rest
  }
}

void RobotRecovery::check_acknowledgements() {
  const double timeout = p_.config.settings.get_double("server.order_ack_timeout_s");
  const long limit = p_.config.settings.get_int("server.order_resend_limit");
  const auto steps = p_.watch.check_acknowledgements(SimClock::wall_now(), timeout, limit, p_.book);
  for (const orders::RecoveryStep& step : steps) {
    const Order& order = *p_.book.find(step.order_id);
    if (step.action == Recovery::kResend) {
      p_.log->warn("order {} not acknowledged by {} within {} s; re-sending ({}/{})", step.order_id, step.robot_id,
                   timeout, step.resends, limit);
      p_.wire.assign(order);
      continue;
    }
    p_.book.requeue(step.order_id, p_.clock.now(), "not acknowledged by " + step.robot_id);
    p_.log->warn("order {} re-queued: never acknowledged by {}", step.order_id, step.robot_id);
    p_.wire.publish(order);
    p_.wire.withdraw(order, step.robot_id);
  }
}

}  // namespace fleet::server
