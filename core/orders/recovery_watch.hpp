#pragma once
// The orders the server watches for their robots' sake: assignments awaiting the robot's
// acknowledgement (and how often each was sent again), and orders waiting for their lost robot.
// The watch keeps that state and, at each check, says what becomes of each order
// (orders::order_recovery decides); the server carries the steps out (book, storage, DDS).
// Times are wall seconds handed in by the caller: no clock here.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "orders/area_ledger.hpp"
#include "orders/order_book.hpp"
#include "orders/order_recovery.hpp"

namespace fleet::orders {

/// One decision on one order, for the server to carry out.
struct RecoveryStep {
  std::int64_t order_id = 0;
  std::string robot_id;  ///< the order's robot when the step was decided
  Recovery action = Recovery::kKeep;
  bool withdraw = false;  ///< also tell robot_id to drop the order (a restarted robot running it)
  long resends = 0;       ///< kResend: how many times the assignment has now been sent again
};

/// What a robot that answers again says of itself (its first RobotState after being lost).
struct ReturningRobot {
  std::string robot_id;
  std::int64_t order_id = 0;   ///< the order its state names (0: none)
  bool carrying_load = false;  ///< a load on its forks
};

class RecoveryWatch {
 public:
  /// The order was (re)assigned to a robot: its count of resends starts over.
  void assigned(std::int64_t order_id);
  /// The assignment went out (or out again) at `now_wall`: the robot's acknowledgement is awaited.
  void sent(std::int64_t order_id, double now_wall);
  /// The robot answered on the order, or the order left it (re-queued, failed): nothing is awaited.
  void settled(std::int64_t order_id);
  /// Only the order's lost robot can finish it: the order waits for it from `now_wall`.
  void wait_for_lost_robot(std::int64_t order_id, double now_wall);
  /// The order went (back) to the robot that has its load: it waits for nobody, resends start over.
  void handed_back(std::int64_t order_id);

  /// `robot` answers again: a step (kKeep, kRequeue or kFailReturnLoad) for each open order that
  /// waited for it (orders::when_robot_back); those orders wait no more.
  std::vector<RecoveryStep> robot_back(const ReturningRobot& robot, const OrderBook& book, const AreaLedger& ledger);
  /// The orders whose wait for a lost robot ended at `now_wall` after `wait_limit_s`
  /// (orders::when_waiting): kRequeue or kFailReturnLoad each. Ended orders are dropped silently.
  std::vector<RecoveryStep> check_waiting(double now_wall, double wait_limit_s, const OrderBook& book,
                                          const AreaLedger& ledger);
  /// Assignments unacknowledged after `timeout_s` at `now_wall` (orders::when_unacknowledged):
  /// kResend (counted; the wait starts again at `now_wall`) up to `resend_limit`, then kRequeue
  /// (no longer watched).
  std::vector<RecoveryStep> check_acknowledgements(double now_wall, double timeout_s, long resend_limit,
                                                   const OrderBook& book);

  bool awaits_acknowledgement(std::int64_t order_id) const { return awaiting_ack_since_.contains(order_id); }
  bool waits_for_lost_robot(std::int64_t order_id) const { return awaiting_lost_robot_.contains(order_id); }

 private:
  std::map<std::int64_t, double> awaiting_ack_since_;   ///< order id -> wall time it was (re)sent
  std::map<std::int64_t, long> resends_;                ///< order id -> times sent again since assigned
  std::map<std::int64_t, double> awaiting_lost_robot_;  ///< order id -> wall time its robot was lost
};

}  // namespace fleet::orders
