#include "orders/recovery_watch.hpp"

namespace fleet::orders {

void RecoveryWatch::assigned(std::int64_t order_id) {
  resends_[order_id] = 0;
}

void RecoveryWatch::sent(std::int64_t order_id, double now_wall) {
  awaiting_ack_since_[order_id] = now_wall;
}

void RecoveryWatch::settled(std::int64_t order_id) {
  awaiting_ack_since_.erase(order_id);
  resends_.erase(order_id);
}

void RecoveryWatch::wait_for_lost_robot(std::int64_t order_id, double now_wall) {
  awaiting_lost_robot_.emplace(order_id, now_wall);
}

void RecoveryWatch::handed_back(std::int64_t order_id) {
  awaiting_lost_robot_.erase(order_id);
  resends_[order_id] = 0;
}

std::vector<RecoveryStep> RecoveryWatch::robot_back(const ReturningRobot& robot, const OrderBook& book,
                                                    const AreaLedger& ledger) {
  std::vector<RecoveryStep> steps;
  for (auto it = awaiting_lost_robot_.begin(); it != awaiting_lost_robot_.end();) {
    const Order* order = book.find(it->first);
    if (!order || order->robot_id != robot.robot_id) {
      ++it;
      continue;
    }
    const std::int64_t id = it->first;
    it = awaiting_lost_robot_.erase(it);
    const auto decision = when_robot_back({.order_open = !is_final(order->status),
                                           .reports_this_order = robot.order_id == id,
                                           .robot_carries_load = ledger.carried_by(robot.robot_id) != nullptr,
                                           .reports_carrying = robot.carrying_load,
                                           .phase = order->phase});
    if (decision.action == Recovery::kForget) continue;
    steps.push_back(
        {.order_id = id, .robot_id = robot.robot_id, .action = decision.action, .withdraw = decision.withdraw});
  }
  return steps;
}

std::vector<RecoveryStep> RecoveryWatch::check_waiting(double now_wall, double wait_limit_s, const OrderBook& book,
                                                       const AreaLedger& ledger) {
  std::vector<RecoveryStep> steps;
  for (auto it = awaiting_lost_robot_.begin(); it != awaiting_lost_robot_.end();) {
    const Order* order = book.find(it->first);
    const auto decision = when_waiting({.order_open = order && !is_final(order->status),
                                        .waited_s = now_wall - it->second,
                                        .wait_limit_s = wait_limit_s,
                                        .robot_carries_load = order && ledger.carried_by(order->robot_id) != nullptr});
    if (decision == Recovery::kWait) {
      ++it;
      continue;
    }
    const std::int64_t id = it->first;
    it = awaiting_lost_robot_.erase(it);
    if (decision != Recovery::kForget)
      steps.push_back({.order_id = id, .robot_id = order->robot_id, .action = decision});
  }
  return steps;
}

std::vector<RecoveryStep> RecoveryWatch::check_acknowledgements(double now_wall, double timeout_s, long resend_limit,
                                                                const OrderBook& book) {
  std::vector<RecoveryStep> steps;
  for (auto it = awaiting_ack_since_.begin(); it != awaiting_ack_since_.end();) {
    const std::int64_t id = it->first;
    const Order* order = book.find(id);
    const auto sent_again = resends_.find(id);
    const auto decision = when_unacknowledged({.still_assigned = order && order->status == OrderStatus::kAssigned,
                                               .waited_s = now_wall - it->second,
                                               .timeout_s = timeout_s,
                                               .resends = sent_again == resends_.end() ? 0 : sent_again->second,
                                               .resend_limit = resend_limit});
    if (decision == Recovery::kWait) {
      ++it;
    } else if (decision == Recovery::kResend) {
      const long count = ++resends_[id];
      it->second = now_wall;
      steps.push_back({.order_id = id, .robot_id = order->robot_id, .action = decision, .resends = count});
      ++it;
    } else {
      if (decision != Recovery::kForget)
        steps.push_back({.order_id = id, .robot_id = order->robot_id, .action = decision});
      resends_.erase(id);
      it = awaiting_ack_since_.erase(it);
    }
  }
  return steps;
}

}  // namespace fleet::orders
