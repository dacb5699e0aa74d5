#include "monitor/collision_monitor.hpp"

#include <cmath>

namespace fleet::monitor {

std::vector<Collision> CollisionMonitor::update(const std::string& robot_id, const geometry::Pose2& pose,
                                                const geometry::Footprint& footprint, double sim_time) {
  std::vector<Collision> started;
  if (!geometry::is_finite(pose)) return started;
  truths_[robot_id] = {pose, footprint, sim_time};
  const geometry::Polygon mine = geometry::footprint_polygon(pose, footprint);
  for (const auto& [other_id, other] : truths_) {
    if (other_id == robot_id || std::abs(other.sim_time - sim_time) > max_skew_) continue;
    const auto key = robot_id < other_id ? std::make_pair(robot_id, other_id) : std::make_pair(other_id, robot_id);
    const bool overlap =
        geometry::convex_polygons_overlap(mine, geometry::footprint_polygon(other.pose, other.footprint));
    if (overlap && in_contact_.insert(key).second) {
      Collision c{sim_time, robot_id, other_id, pose, other.pose};
      collisions_.push_back(c);
      started.push_back(c);
    } else if (!overlap) {
      in_contact_.erase(key);
    }
  }
  return started;
}

void CollisionMonitor::remove(const std::string& robot_id) {
  truths_.erase(robot_id);
  for (auto it = in_contact_.begin(); it != in_contact_.end();) {
    it = (it->first == robot_id || it->second == robot_id) ? in_contact_.erase(it) : std::next(it);
  }
}

}  // namespace fleet::monitor
