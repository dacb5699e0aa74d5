#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include "model/messages.hpp"

namespace fleet::orders {

/// What an agent does with an order assignment addressed to its robot.
enum class IntakeStep {
  kIgnore,             ///< a late duplicate of an order it knows no end of, or a stale withdrawal
  kRepeatFinalReport,  ///< a late duplicate of an order it ended: it says again how it ended
  kWithdraw,           ///< the server withdraws the order the robot runs
  kAcknowledgeAgain,   ///< the order the robot runs, sent again (a lost acknowledgement, a restart)
  kConsider,           ///< a new order: checked (refusal_of) and submitted to the robot
};

/// The order the robot runs, as the intake needs it.
struct RunningOrder {
  std::int64_t order_id = 0;
  std::uint32_t update_id = 0;
};

/// What a new order is checked against, in this order; each is empty or false when it does not apply.
struct NewOrderChecks {
  std::string invalid;                    ///< the order itself is wrong: an unknown kind, a bad pick line
  std::optional<std::int64_t> busy_with;  ///< the order the robot runs
  std::string robot_refusal;              ///< the robot type cannot do this kind
  bool paused = false;                    ///< the operator paused the robot
};

/// An agent's order rules: which assignments are new, late duplicates, withdrawals or re-sends
/// (update ids grow with every change of an order, as VDA 5050's orderUpdateId does), and why a
/// new one is refused. It keeps the newest update seen per order and the final reports of the
/// last orders the robot ended, to repeat to a server that offers one of them again. Free of
/// DDS: the agent carries the steps out.
class AssignmentIntake {
 public:
  /// Final reports kept by default: a restarted server only asks about its recent orders, and
  /// each kept report is a latched sample the agent's writer holds.
  static constexpr std::size_t kKeptReports = 8;
  explicit AssignmentIntake(std::size_t kept_reports = kKeptReports) : kept_reports_(kept_reports) {}

  /// The step for `assignment` given the order the robot runs, and remembers its update.
  IntakeStep classify(const model::OrderAssignment& assignment, const std::optional<RunningOrder>& running);
  /// Why a new order is refused, the first check that applies; "" when the robot may take it.
  static std::string refusal_of(const NewOrderChecks& checks);
  /// Keeps the final report of an order the robot ended; returns the report no longer kept, if
  /// one drops out (its latched sample can be unregistered).
  std::optional<model::OrderReport> remember_end(const model::OrderReport& report);
  /// The kept final report of an order, nullptr when none.
  const model::OrderReport* final_report(std::int64_t order_id) const;

 private:
  std::size_t kept_reports_;
  std::map<std::int64_t, std::uint32_t> seen_updates_;  ///< order id -> newest update id handled
  std::deque<model::OrderReport> final_reports_;        ///< oldest first
};

}  // namespace fleet::orders
