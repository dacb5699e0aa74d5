#include "orders/order_recovery.hpp"

#include <algorithm>

namespace fleet::orders {

std::string_view to_string(Recovery decision) {
  switch (decision) {
    case Recovery::kKeep:
      return "keep";
    case Recovery::kWait:
      return "wait";
    case Recovery::kResend:
      return "resend";
    case Recovery::kRequeue:
      return "requeue";
    case Recovery::kFailReturnLoad:
      return "fail-return-load";
    case Recovery::kWithdraw:
      return "withdraw";
    case Recovery::kForget:
      return "forget";
  }
  return "?";
}

std::string_view to_string(ReportVerdict verdict) {
  switch (verdict) {
    case ReportVerdict::kApply:
      return "apply";
    case ReportVerdict::kHandBack:
      return "hand-back";
    case ReportVerdict::kStale:
      return "stale";
    case ReportVerdict::kRepeated:
      return "repeated";
    case ReportVerdict::kWithdraw:
      return "withdraw";
  }
  return "?";
}

bool at_pick_place(OrderPhase phase) {
  return phase == OrderPhase::kSearching || phase == OrderPhase::kPicking;
}

bool past_the_lift(OrderPhase phase) {
  return phase == OrderPhase::kToDrop || phase == OrderPhase::kDropping;
}

Recovery when_robot_lost(const LostRobotFacts& facts) {
  // Lost at the pick place, searching or picking, it may be lifting the load as it froze, or do
  // so within a second of answering again, before a withdrawal reaches it: like one lost with the
  // load on its forks, only this robot can finish the order, and a stalled robot carries on when
  // it answers again. (Re-queued instead, the order was withdrawn from it as it came back with
  // the load, and it stood in the lane with it for good.)
  if (facts.reports_carrying || facts.carries_boxes || at_pick_place(facts.phase)) return Recovery::kWait;
  return Recovery::kRequeue;
}

bool boxes_aboard(const Order& order) {
  if (order.kind != OrderKind::kPick) return false;
  for (auto e = order.history.rbegin(); e != order.history.rend(); ++e) {
    if (e->status == OrderStatus::kAssigned || e->status == OrderStatus::kQueued) return false;
    if (e->phase == OrderPhase::kPicking) return true;
  }
  return false;
}

Recovery when_giving_up(bool robot_carries_load) {
  // Lost at the pick place before the lift, the load still stands there for another robot.
  return robot_carries_load ? Recovery::kFailReturnLoad : Recovery::kRequeue;
}

Recovery when_waiting(const WaitingOrderFacts& facts) {
  if (!facts.order_open) return Recovery::kForget;
  if (facts.waited_s <= facts.wait_limit_s) return Recovery::kWait;
  return when_giving_up(facts.robot_carries_load);
}

RobotBackDecision when_robot_back(const RobotBackFacts& facts) {
  if (!facts.order_open) return {Recovery::kForget, false};
  // A restarted agent may report the order too: it read the latched assignment before its first
  // state, and runs the order from the start. Its forks are empty while the load truth has the
  // load on them (and it was not putting it down). The order's phase does not tell: the
  // restarted agent's TO_PICK report can arrive before its first state.
  const bool dropping = facts.phase == OrderPhase::kDropping;
  const bool restarted =
      !facts.reports_this_order || (facts.robot_carries_load && !facts.reports_carrying && !dropping);
  // Not restarted, its software still runs the order: the load is on its forks, or it was put
  // down at the drop place as the robot froze and the DONE report follows, or it was still at
  // the pick.
  if (!restarted) return {Recovery::kKeep, false};
  return {when_giving_up(facts.robot_carries_load), facts.reports_this_order};
}

Recovery when_robot_reappears(const ReappearingFacts& facts) {
  return facts.order_final || !facts.order_is_robots ? Recovery::kWithdraw : Recovery::kKeep;
}

Recovery when_unacknowledged(const AcknowledgementFacts& facts) {
  if (facts.waited_s < facts.timeout_s) return Recovery::kWait;
  if (!facts.still_assigned) return Recovery::kForget;
  return facts.resends < facts.resend_limit ? Recovery::kResend : Recovery::kRequeue;
}

double restart_grace_s(double robot_lost_after_s) {
  return std::max(3.0, 3.0 * robot_lost_after_s);
}

bool restored_robot_carried_load(OrderPhase phase) {
  return past_the_lift(phase);
}

bool hands_back(const ReportFacts& facts) {
  // A robot lost on its way to the pick had its order re-queued; answering again, it may reach
  // the pick place, search and lift the load before the withdrawal reaches it. It cannot put the
  // load back and carries the order on; no other robot can pick that load now. So the order
  // goes back to it, unless its new robot has lifted a load for it already.
  const auto phase = parse_phase(facts.reported);
  const bool lifted = facts.reports_carrying && phase && past_the_lift(*phase);
  if (!lifted || facts.from_order_robot || is_final(facts.order_status)) return false;
  if (facts.order_phase == OrderPhase::kPicking || past_the_lift(facts.order_phase)) return false;
  // Counted lost still, it is back all the same: its report may come before its first state (and
  // is not sent again), and was written after it fell silent.
  return facts.reporter_registered;
}

ReportVerdict judge_report(const ReportFacts& facts) {
  if (!facts.from_order_robot || !facts.current_update) {
    return hands_back(facts) ? ReportVerdict::kHandBack : ReportVerdict::kStale;
  }
  // Reports are kept for late joiners: a restarted server hears every robot's finished orders
  // again. The same end state twice is news to no one.
  if ((facts.reported == "DONE" && facts.order_status == OrderStatus::kDone) ||
      (facts.reported == "FAILED" && facts.order_status == OrderStatus::kFailed)) {
    return ReportVerdict::kRepeated;
  }
  // The robot runs an order that has ended: it read the latched assignment as it restarted, just
  // before the order was failed for its return with empty forks. Left alone, it would carry a
  // load for an order no one counts.
  if (is_final(facts.order_status)) return ReportVerdict::kWithdraw;
  return ReportVerdict::kApply;
}

}  // namespace fleet::orders
