#include "orders/assignment_intake.hpp"

#include <algorithm>

namespace fleet::orders {

IntakeStep AssignmentIntake::classify(const model::OrderAssignment& assignment,
                                      const std::optional<RunningOrder>& running) {
  const bool is_running = running && running->order_id == assignment.order_id;
  const auto seen = seen_updates_.find(assignment.order_id);
  const bool duplicate = seen != seen_updates_.end() && assignment.update_id <= seen->second;
  if (duplicate && !assignment.cancelled && !is_running) {
    // A late duplicate, or the assignment of an order this robot ended, re-sent by a server that
    // restarted without hearing how it ended: the latched report should have told it, and this
    // does not depend on that.
    return final_report(assignment.order_id) != nullptr ? IntakeStep::kRepeatFinalReport : IntakeStep::kIgnore;
  }
  seen_updates_[assignment.order_id] = std::max(assignment.update_id, duplicate ? seen->second : 0U);
  if (assignment.cancelled) {
    // A withdrawal older than the assignment the robot runs is a late duplicate.
    return is_running && assignment.update_id >= running->update_id ? IntakeStep::kWithdraw : IntakeStep::kIgnore;
  }
  return is_running ? IntakeStep::kAcknowledgeAgain : IntakeStep::kConsider;
}

std::string AssignmentIntake::refusal_of(const NewOrderChecks& checks) {
  if (!checks.invalid.empty()) return checks.invalid;
  if (checks.busy_with) return "busy with order " + std::to_string(*checks.busy_with);
  if (!checks.robot_refusal.empty()) return checks.robot_refusal;
  if (checks.paused) return "paused by the operator";
  return "";
}

std::optional<model::OrderReport> AssignmentIntake::remember_end(const model::OrderReport& report) {
  final_reports_.push_back(report);
  if (final_reports_.size() <= kept_reports_) return std::nullopt;
  model::OrderReport dropped = std::move(final_reports_.front());
  final_reports_.pop_front();
  return dropped;
}

const model::OrderReport* AssignmentIntake::final_report(std::int64_t order_id) const {
  const auto it = std::find_if(final_reports_.rbegin(), final_reports_.rend(),
                               [&](const model::OrderReport& r) { return r.order_id == order_id; });
  return it == final_reports_.rend() ? nullptr : &*it;
}

}  // namespace fleet::orders
