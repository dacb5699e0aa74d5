#include "cli/order_progress.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "orders/order.hpp"

namespace fleet::cli {

namespace {

/// Sim time the order entered its current stage: the first event of the last run of events in
/// that stage.
double stage_entered(const model::OrderInfo& order) {
  const std::string stage = stage_of(order.state, order.phase);
  double entered = order.updated_sim;
  for (auto e = order.history.rbegin(); e != order.history.rend(); ++e) {
    if (stage_of(e->state, e->phase) != stage) break;
    entered = e->sim_time;
  }
  return entered;
}

double round_tenth(double v) {
  return std::round(v * 10.0) / 10.0;
}

}  // namespace

std::string stage_of(const std::string& state, const std::string& phase) {
  if (state == "ACTIVE" && !phase.empty()) return phase;
  return state;
}

bool is_final_state(const std::string& state) {
  const auto status = orders::parse_status(state);
  return status && orders::is_final(*status);
}

DurationModel::DurationModel(const std::map<std::int64_t, model::OrderInfo>& orders) {
  for (const auto& [id, order] : orders) {
    if (order.state != "DONE" || order.history.empty() || order.history.back().state != "DONE") continue;
    const double done_at = order.history.back().sim_time;
    // When each stage was last entered; a re-queued order starts over, so QUEUED forgets the
    // stages of the earlier attempt.
    std::map<std::string, double> entered;
    std::string previous;
    for (const auto& e : order.history) {
      const std::string stage = stage_of(e.state, e.phase);
      if (stage == "QUEUED") entered.clear();
      if (stage != previous) entered[stage] = e.sim_time;
      previous = stage;
    }
    entered.erase("DONE");
    entered.erase("QUEUED");
    if (entered.empty()) continue;
    ++done_orders_;
    for (const auto& [stage, at] : entered) {
      auto& [sum, count] = sums_[stage];
      sum += done_at - at;
      ++count;
    }
  }
}

std::optional<double> DurationModel::mean_to_done(const std::string& stage) const {
  const auto it = sums_.find(stage);
  if (it == sums_.end() || it->second.second == 0) return std::nullopt;
  return it->second.first / it->second.second;
}

OrderProgress progress_of(const model::OrderInfo& order, const DurationModel& durations, double now_sim) {
  OrderProgress progress;
  if (is_final_state(order.state)) {
    progress.elapsed_s = std::max(0.0, order.updated_sim - order.created_sim);
    progress.left_s = 0.0;
    return progress;
  }
  progress.elapsed_s = std::max(0.0, now_sim - order.created_sim);
  if (order.state == "QUEUED") return progress;
  const std::string stage = stage_of(order.state, order.phase);
  if (const auto mean = durations.mean_to_done(stage)) {
    progress.left_s = std::max(0.0, *mean - (now_sim - stage_entered(order)));
    return progress;
  }
  if (const auto work = durations.mean_work()) {
    // No DONE order went through this stage (an order restored mid-way, say): use the whole
    // assignment-to-DONE mean from the last assignment.
    double assigned = order.created_sim;
    for (const auto& e : order.history) {
      if (e.state == "ASSIGNED") assigned = e.sim_time;
    }
    progress.left_s = std::max(0.0, *work - (now_sim - assigned));
  }
  return progress;
}

std::string progress_line(const model::OrderInfo& order, const OrderProgress& progress) {
  std::ostringstream line;
  line << std::fixed << std::setprecision(1) << "order " << order.order_id << " " << order.pick_area << " -> "
       << order.drop_area << "  " << order.state;
  if (order.state == "ACTIVE" && !order.phase.empty()) line << " " << order.phase;
  line << "  " << (order.robot_id.empty() ? "-" : order.robot_id) << "  elapsed " << progress.elapsed_s << " s";
  if (!is_final_state(order.state)) {
    line << "  left ";
    if (progress.left_s) {
      line << *progress.left_s << " s";
    } else {
      line << "?";
    }
  }
  if (!order.reason.empty()) line << ": " << order.reason;
  return line.str();
}

nlohmann::json progress_json(const model::OrderInfo& order, const OrderProgress& progress) {
  return {{"order_id", order.order_id},
          {"pick_area", order.pick_area},
          {"drop_area", order.drop_area},
          {"state", order.state},
          {"phase", order.phase},
          {"robot_id", order.robot_id},
          {"reason", order.reason},
          {"elapsed_s", round_tenth(progress.elapsed_s)},
          {"left_s", progress.left_s ? nlohmann::json(round_tenth(*progress.left_s)) : nlohmann::json(nullptr)}};
}

std::string change_key(const model::OrderInfo& order) {
  return order.state + "|" + order.phase + "|" + order.robot_id + "|" + order.reason;
}

}  // namespace fleet::cli
