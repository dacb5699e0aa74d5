#pragma once

#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "model/messages.hpp"

namespace fleet::cli {

/// How long orders take from each stage to DONE, learnt from the histories of the orders already
/// DONE. A stage is ASSIGNED, or while ACTIVE the phase (TO_PICK, SEARCHING, PICKING, TO_DROP,
/// DROPPING). Per stage, because an order in TO_DROP has far less left than one just assigned.
class DurationModel {
 public:
  explicit DurationModel(const std::map<std::int64_t, model::OrderInfo>& orders);

  /// Mean sim seconds from entering `stage` to DONE over the DONE orders that went through it.
  std::optional<double> mean_to_done(const std::string& stage) const;
  /// Mean sim seconds from the (last) assignment to DONE; nothing before any order is DONE.
  std::optional<double> mean_work() const { return mean_to_done("ASSIGNED"); }
  int done_orders() const { return done_orders_; }

 private:
  std::map<std::string, std::pair<double, int>> sums_;  ///< stage -> (sum of seconds, count)
  int done_orders_ = 0;
};

/// The stage an order is in: "QUEUED", "ASSIGNED", a phase while ACTIVE, or its final state.
std::string stage_of(const std::string& state, const std::string& phase);

/// Where one order stands, in sim seconds.
struct OrderProgress {
  double elapsed_s = 0.0;        ///< since it was created; creation to end once it ended
  std::optional<double> left_s;  ///< estimate; nothing while queued or before any order is DONE
};

/// Estimated time left: the mean time from the current stage to DONE minus the time already
/// spent in it (falling back to the whole assignment-to-DONE mean for a stage no DONE order went
/// through), never below 0. 0 once the order ended.
OrderProgress progress_of(const model::OrderInfo& order, const DurationModel& durations, double now_sim);

/// "order 7 A1 -> A2  ACTIVE TO_DROP  fl1  elapsed 23.4 s  left 12.0 s" (left ? when unknown),
/// with ": reason" when the order has one.
std::string progress_line(const model::OrderInfo& order, const OrderProgress& progress);

/// The same as one JSON object (left_s null when unknown).
nlohmann::json progress_json(const model::OrderInfo& order, const OrderProgress& progress);

/// What makes a new line in a watch: state, phase, robot or reason changed.
std::string change_key(const model::OrderInfo& order);

bool is_final_state(const std::string& state);

}  // namespace fleet::cli
