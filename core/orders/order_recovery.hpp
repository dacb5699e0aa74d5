#pragma once
// What becomes of an order when its robot is in trouble: lost, back after a silence, restarted,
// late to acknowledge, or reporting on an order the server has moved on from. Each function
// takes the facts the server knows and returns a decision; the server carries it out (book,
// storage, DDS). No clocks here: elapsed times come in as facts.

#include <string_view>

#include "orders/order.hpp"

namespace fleet::orders {

/// What the server does with one order.
enum class Recovery {
  kKeep,            ///< nothing changes: the robot carries on with the order
  kWait,            ///< the order waits (bounded) for its robot: only that robot can finish it
  kResend,          ///< the assignment goes out again
  kRequeue,         ///< back to the queue, withdrawn from its robot
  kFailReturnLoad,  ///< failed; the load its robot carried goes back onto a place
  kWithdraw,        ///< the robot is told to drop the order; the order itself is unchanged
  kForget,          ///< the order needs no more watching (it ended, or is no longer assigned)
};

std::string_view to_string(Recovery decision);

/// Searching or picking: the robot stands at the pick place, the load perhaps on its way up.
bool at_pick_place(OrderPhase phase);

/// Driving to the drop or putting the load down: it was lifted.
bool past_the_lift(OrderPhase phase);

/// A robot with an open order is lost (silent, or its DDS lease ran out).
struct LostRobotFacts {
  OrderPhase phase = OrderPhase::kNone;  ///< the order's phase as last reported
  bool reports_carrying = false;         ///< the robot's last state had a load on its forks
  bool carries_boxes = false;            ///< a pick tour it has picked boxes for (boxes_aboard)
};

/// kWait when only the lost robot can finish the order (the load or the tour's boxes are on it,
/// or it may be lifting the load as it froze at the pick place); kRequeue otherwise.
Recovery when_robot_lost(const LostRobotFacts& facts);

/// A pick tour whose robot has picked since it was last assigned the tour: boxes of it ride on
/// that robot's tray, and another picker sent for them would pick them a second time.
bool boxes_aboard(const Order& order);

/// The server gives up on a lost robot's order (it came back restarted, or not at all in time).
/// kRequeue when the load truth does not have the load on the robot (it still stands at the pick
/// place); kFailReturnLoad when it does: no other robot can finish that order.
Recovery when_giving_up(bool robot_carries_load);

/// An order waiting for its lost robot, checked while the robot stays silent.
struct WaitingOrderFacts {
  bool order_open = true;  ///< known and not final
  double waited_s = 0.0;   ///< wall seconds since the robot was lost
  double wait_limit_s = 0.0;
  bool robot_carries_load = false;  ///< by the load truth
};

/// kForget once the order ended, kWait within the limit, then when_giving_up.
Recovery when_waiting(const WaitingOrderFacts& facts);

/// The lost robot of a waiting order answers again, with its first RobotState.
struct RobotBackFacts {
  bool order_open = true;           ///< known and not final
  bool reports_this_order = false;  ///< its state names the waiting order
  bool robot_carries_load = false;  ///< by the load truth
  bool reports_carrying = false;    ///< its state has a load on its forks
  OrderPhase phase = OrderPhase::kNone;
};

struct RobotBackDecision {
  Recovery action = Recovery::kKeep;  ///< kForget, kKeep, kRequeue or kFailReturnLoad
  bool withdraw = false;              ///< also tell the robot to drop the order it reports
};

/// The robot was restarted when it names another order (or none), or when the load truth has
/// the load on its forks while they are empty and it was not putting the load down: then the
/// server gives up (when_giving_up), and a restarted robot that runs the order from the start is
/// told to drop it. Otherwise its software still runs the order: kKeep.
RobotBackDecision when_robot_back(const RobotBackFacts& facts);

/// A robot registers or comes back naming an order in its state.
struct ReappearingFacts {
  bool order_final = false;
  bool order_is_robots = true;  ///< the order is still assigned to this robot
};

/// kWithdraw when the server moved on from the order (ended, or given to another robot), so the
/// robot stops running it; kKeep otherwise.
Recovery when_robot_reappears(const ReappearingFacts& facts);

/// An assignment awaiting the robot's acknowledgement.
struct AcknowledgementFacts {
  bool still_assigned = true;  ///< the order is known and ASSIGNED (not yet accepted)
  double waited_s = 0.0;       ///< wall seconds since it was (re)sent
  double timeout_s = 0.0;
  long resends = 0;  ///< times it was re-sent already
  long resend_limit = 0;
};

/// kWait within the timeout; kForget once the order moved on; kResend up to the limit; then
/// kRequeue (never acknowledged).
Recovery when_unacknowledged(const AcknowledgementFacts& facts);

/// An order restored from storage whose robot has not reported since the restart counts as lost
/// once this grace period (wall seconds since the start) is over.
double restart_grace_s(double robot_lost_after_s);

/// Such a robot had the load on board when the order's phase was past the lift.
bool restored_robot_carried_load(OrderPhase phase);

/// A report of a robot on one of its orders (OrderState), against the order as the server knows it.
struct ReportFacts {
  OrderStatus order_status = OrderStatus::kQueued;
  OrderPhase order_phase = OrderPhase::kNone;
  bool from_order_robot = true;  ///< the reporting robot holds the order
  bool current_update = true;    ///< the report names the order's current update id
  std::string_view reported;     ///< the status or phase reported: "ACCEPTED", "DONE", "TO_DROP", ...
  bool reports_carrying = false;
  bool reporter_registered = true;  ///< the reporting robot has reported its state to this server
};

enum class ReportVerdict {
  kApply,     ///< a current report: the lifecycle takes it
  kHandBack,  ///< the order goes (back) to the reporting robot, which lifted its load
  kStale,     ///< a late duplicate, or from a robot the order was taken from: ignored
  kRepeated,  ///< the end state the order already has (reports are latched): ignored
  kWithdraw,  ///< the order has ended but the robot runs it: told to drop it
};

std::string_view to_string(ReportVerdict verdict);

/// A report from a robot the order was taken from, past the lift with the load on its forks,
/// while no robot holding the order has reached the pick: the order goes back to it (no cancel
/// after the pick [Forklift thesis, section 6.4]), once that robot is registered again.
bool hands_back(const ReportFacts& facts);

/// The verdict on a report: kHandBack or kStale when it is not current, kRepeated for the same
/// end state again, kWithdraw when the order ended, else kApply.
ReportVerdict judge_report(const ReportFacts& facts);

}  // namespace fleet::orders
