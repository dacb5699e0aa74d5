#include "orders/robot_roster.hpp"

#include <algorithm>
#include <vector>

#include "geometry/convex_hull.hpp"
#include "orders/transport_areas.hpp"

namespace fleet::orders {

bool RobotRoster::registered(const std::string& robot_id) const {
  const auto it = entries_.find(robot_id);
  return it != entries_.end() && it->second.registered;
}

std::set<std::string> RobotRoster::registered_ids() const {
  std::set<std::string> seen;
  for (const auto& [id, robot] : entries_) {
    if (robot.registered) seen.insert(id);
  }
  return seen;
}

int RobotRoster::registered_count() const {
  return static_cast<int>(
      std::count_if(entries_.begin(), entries_.end(), [](const auto& entry) { return entry.second.registered; }));
}

geometry::Polygon RobotRoster::body_of(const RobotEntry& robot) const {
  const auto spec = config_.find_robot(robot.id);
  if (!spec) return geometry::footprint_polygon(robot.last.pose, geometry::Footprint{});
  std::vector<geometry::Vec2> corners;
  for (const auto& p : spec->first->profile.footprint) corners.push_back(geometry::body_to_map(robot.last.pose, p));
  return geometry::convex_hull(std::move(corners));
}

std::string RobotRoster::robot_under(const geometry::Polygon& area) const {
  for (const auto& [id, robot] : entries_) {
    if (robot.registered && geometry::polygons_overlap(area, body_of(robot))) return id;
  }
  return "";
}

bool RobotRoster::someone_stands_on(const map::LoadingArea& area, double approach_distance) const {
  // Bodies are a few metres long at most: robots farther than this from the place are not shaped.
  constexpr double kNearM = 5.0;
  for (const auto& [id, robot] : entries_) {
    if (!robot.registered || geometry::distance(robot.last.pose.position(), area.pose.position()) > kNearM) continue;
    if (body_stands_on(body_of(robot), area, approach_distance)) return true;
  }
  return false;
}

}  // namespace fleet::orders
