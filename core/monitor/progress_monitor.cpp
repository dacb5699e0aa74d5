#include "monitor/progress_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

namespace fleet::monitor {

ProgressMonitor::ProgressMonitor(double timeout_s, double move_threshold, double queue_bound_s, double phase_bound_s)
    : timeout_s_(timeout_s),
      move_threshold_(move_threshold),
      queue_bound_s_(queue_bound_s),
      phase_bound_s_(phase_bound_s) {}

bool ProgressMonitor::update(const std::string& robot_id, const geometry::Pose2& pose, const std::string& task,
                             double t, bool working) {
  auto [it, fresh] = watches_.try_emplace(robot_id);
  Watch& w = it->second;
  if (fresh || task != w.task || task.empty()) {
    w.task_since = t;
    w.task_reported = false;
  }
  const auto report = [&](double since) {
    w.reported = true;
    w.task_reported = true;
    const auto waits = waiting_for_.find(robot_id);
    deadlocks_.push_back(
        {robot_id, task, since, t, pose, waits == waiting_for_.end() ? std::vector<std::string>{} : waits->second});
    return true;
  };
  if (fresh || std::hypot(pose.x - w.moved_from.x, pose.y - w.moved_from.y) > move_threshold_) {
    w.moved_from = pose;
    w.moved_at = t;
  }
  // Moving about without getting anywhere: one phase of its order for longer than any takes.
  if (!task.empty() && !w.task_reported && t - w.task_since >= phase_bound_s_) return report(w.task_since);
  const bool moved = std::hypot(pose.x - w.anchor.x, pose.y - w.anchor.y) > move_threshold_;
  if (fresh || moved || working || task != w.task || task.empty()) {
    w.anchor = pose;
    w.task = task;
    w.since = t;
    w.queue_moved = t;
    w.reported = false;
    return false;
  }
  // Queued, the moves of the robots ahead are its progress, up to the queue bound.
  w.queue_moved = std::max(w.queue_moved, queue_moved_at(robot_id));
  const double stalled = t - std::max(w.since, w.queue_moved);
  if (w.reported || (stalled < timeout_s_ && t - w.since < queue_bound_s_)) return false;
  return report(w.since);
}

void ProgressMonitor::note_waiting_for(const std::string& robot_id, std::vector<std::string> robots) {
  if (robots.empty()) {
    waiting_for_.erase(robot_id);
  } else {
    waiting_for_[robot_id] = std::move(robots);
  }
}

double ProgressMonitor::queue_moved_at(const std::string& robot_id) const {
  double latest = -std::numeric_limits<double>::infinity();
  std::set<std::string> seen{robot_id};
  std::vector<std::string> open{robot_id};
  while (!open.empty()) {
    const std::string at = std::move(open.back());
    open.pop_back();
    const auto waits = waiting_for_.find(at);
    if (waits == waiting_for_.end()) continue;
    for (const auto& other : waits->second) {
      if (!seen.insert(other).second) continue;
      if (const auto watch = watches_.find(other); watch != watches_.end()) {
        latest = std::max(latest, watch->second.moved_at);
      }
      open.push_back(other);
    }
  }
  return latest;
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
  waiting_for_.erase(robot_id);
  waiting_since_.erase(robot_id);
}

double ProgressMonitor::max_wait_s(double now) const {
  double longest = max_wait_s_;
  for (const auto& [id, since] : waiting_since_) longest = std::max(longest, now - since);
  return longest;
}

}  // namespace fleet::monitor
