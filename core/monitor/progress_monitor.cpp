#include "monitor/progress_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::monitor {

ProgressMonitor::ProgressMonitor(double timeout_s, double move_threshold)
    : timeout_s_(timeout_s), move_threshold_(move_threshold) {}

bool ProgressMonitor::update(const std::string& robot_id, const geometry::Pose2& pose, const std::string& task,
                             double t) {
  auto [it, fresh] = watches_.try_emplace(robot_id);
  Watch& w = it->second;
  const bool moved = std::hypot(pose.x - w.anchor.x, pose.y - w.anchor.y) > move_threshold_;
  if (fresh || moved || task != w.task || task.empty()) {
    w.anchor = pose;
    w.task = task;
    w.since = t;
    w.reported = false;
    return false;
  }
  if (w.reported || t - w.since < timeout_s_) return false;
  w.reported = true;
  deadlocks_.push_back({robot_id, task, w.since, t, pose});
  return true;
}

void ProgressMonitor::note_state(const std::string& robot_id, const std::string& task_state, double t) {
  auto it = waiting_since_.find(robot_id);
  if (task_state == "WAITING") {
    if (it == waiting_since_.end()) waiting_since_[robot_id] = t;
    return;
  }
  if (it != waiting_since_.end()) {
    max_wait_s_ = std::max(max_wait_s_, t - it->second);
    waiting_since_.erase(it);
  }
}

void ProgressMonitor::forget(const std::string& robot_id) {
  watches_.erase(robot_id);
  waiting_since_.erase(robot_id);
}

double ProgressMonitor::max_wait_s(double now) const {
  double longest = max_wait_s_;
  for (const auto& [id, since] : waiting_since_) longest = std::max(longest, now - since);
  return longest;
}

}  // namespace fleet::monitor
