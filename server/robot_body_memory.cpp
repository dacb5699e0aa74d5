#include "server/robot_body_memory.hpp"

#include <cmath>

namespace fleet::server {

RobotBodyMemory::RobotBodyMemory(OrderStore& store)
    : store_(store), before_start_(store.load_robot_poses()), stored_(before_start_) {}

void RobotBodyMemory::remember(const std::map<std::string, geometry::Pose2>& heard, double now_wall) {
  if (!due(now_wall)) return;
  next_store_wall_ = now_wall + kEveryS;
  std::map<std::string, geometry::Pose2> moved;
  for (const auto& [id, pose] : heard) {
    const auto it = stored_.find(id);
    if (it != stored_.end() && std::hypot(pose.x - it->second.x, pose.y - it->second.y) <= kMovedM &&
        std::abs(std::remainder(pose.yaw - it->second.yaw, 2.0 * M_PI)) <= kMovedRad) {
      continue;
    }
    moved[id] = pose;
  }
  store_.save_robot_poses(moved);
  for (const auto& [id, pose] : moved) stored_[id] = pose;
}

}  // namespace fleet::server
