#include "monitor/localization_watch.hpp"

#include <algorithm>
#include <cmath>

#include "common/percentile.hpp"
#include "monitor/order_accounting.hpp"

namespace fleet::monitor {

namespace {
// Two stamps closer than this are one publication (they are equal when they are).
constexpr double kSameStamp = 1e-6;
}  // namespace

void LocalizationWatch::note_estimate(const std::string& robot_id, const geometry::Pose2& estimate, double sim_time) {
  estimates_[robot_id] = {estimate, sim_time};
  compare(robot_id);
}

void LocalizationWatch::note_truth(const std::string& robot_id, const geometry::Pose2& truth, double sim_time) {
  truths_[robot_id] = {truth, sim_time};
  compare(robot_id);
}

void LocalizationWatch::compare(const std::string& robot_id) {
  const auto e = estimates_.find(robot_id);
  const auto t = truths_.find(robot_id);
  if (e == estimates_.end() || t == truths_.end()) return;
  if (e->second.sim_time < 0.0 || std::abs(e->second.sim_time - t->second.sim_time) > kSameStamp) return;
  if (!geometry::is_finite(e->second.pose) || !geometry::is_finite(t->second.pose)) return;
  const double error = geometry::distance(e->second.pose.position(), t->second.pose.position());
  errors_[robot_id].push_back(error);
  const Worst here{error, t->second.sim_time, t->second.pose, e->second.pose};
  if (Worst& w = worst_[robot_id]; error >= w.error) w = here;
  bool& off = far_off_[robot_id];
  if (!off && error >= off_after_) new_far_off_.push_back({robot_id, here});
  off = off ? error >= back_under_ : error >= off_after_;
  e->second.sim_time = -1.0;  // each publication once
}

std::vector<LocalizationWatch::FarOff> LocalizationWatch::take_far_off() {
  std::vector<FarOff> out;
  out.swap(new_far_off_);
  return out;
}

std::map<std::string, ErrorFigures> error_figures(const std::map<std::string, std::vector<double>>& errors,
                                                  const std::map<std::string, std::string>& group_of) {
  std::map<std::string, std::vector<double>> grouped;
  for (const auto& [robot, values] : errors) {
    const auto g = group_of.find(robot);
    auto& into = grouped[g == group_of.end() ? robot : g->second];
    into.insert(into.end(), values.begin(), values.end());
  }
  std::map<std::string, ErrorFigures> figures;
  for (const auto& [group, values] : grouped) {
    if (values.empty()) continue;
    figures[group] = {common::percentile(values, 0.95), *std::max_element(values.begin(), values.end()),
                      static_cast<long>(values.size())};
  }
  return figures;
}

}  // namespace fleet::monitor
