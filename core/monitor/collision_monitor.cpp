#include "monitor/collision_monitor.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::monitor {

namespace {

geometry::Polygon placed(const geometry::Polygon& body, const geometry::Pose2& pose) {
  geometry::Polygon out;
  out.reserve(body.size());
  for (const auto& p : body) out.push_back(geometry::body_to_map(pose, p));
  return out;
}

}  // namespace

std::vector<Collision> CollisionMonitor::update(const std::string& robot_id, const geometry::Pose2& pose,
                                                const geometry::Footprint& footprint, double sim_time) {
  // The rectangle in the body frame: the footprint polygon at the origin.
  return update(robot_id, pose, geometry::footprint_polygon({0.0, 0.0, 0.0}, footprint), sim_time);
}

std::vector<Collision> CollisionMonitor::update(const std::string& robot_id, const geometry::Pose2& pose,
                                                const geometry::Polygon& body, double sim_time) {
  std::vector<Collision> started;
  if (!geometry::is_finite(pose)) return started;
  double radius = 0.0;
  for (const auto& p : body) radius = std::max(radius, std::hypot(p.x, p.y));
  truths_[robot_id] = {pose, body, radius, sim_time};
  const geometry::Polygon mine = placed(body, pose);
  for (const auto& [other_id, other] : truths_) {
    if (other_id == robot_id || std::abs(other.sim_time - sim_time) > max_skew_) continue;
    // Bodies whose bounding circles are apart cannot touch: with hundreds of robots most pairs
    // end here, before any polygon is placed.
    const bool near = std::hypot(other.pose.x - pose.x, other.pose.y - pose.y) <= radius + other.radius;
    if (!near && in_contact_.empty()) continue;
    const auto key = robot_id < other_id ? std::make_pair(robot_id, other_id) : std::make_pair(other_id, robot_id);
    // Footprints of vehicle profiles may be concave: the general test.
    const bool overlap = near && geometry::polygons_overlap(mine, placed(other.body, other.pose));
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
