// The TrafficManager's arrival areas: what a robot sweeps turning off its route into a place
// beside the road, held with the route's last point; and the ways out that docked robots will
// sweep turning back onto it, kept clear of stopping robots.

#include <algorithm>

#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_manager_detail.hpp"

namespace fleet::traffic {

using detail::sort_unique;

namespace {

bool same_area(const geometry::Polygon& a, const geometry::Polygon& b) {
  constexpr double kMovedM = 0.01;
  return geometry::same_polygon(a, b, kMovedM);
}

}  // namespace

void TrafficManager::set_arrival_area(int robot_id, int goal_point, const geometry::Polygon& area) {
  auto it = robots_.find(robot_id);
  if (it == robots_.end()) return;
  Robot& robot = it->second;
  if (robot.frozen || robot.arrival_held) return;  // a new route lets a held area go (leave_arrival)
  if (area.size() < 3 || goal_point < 0 || static_cast<std::size_t>(goal_point) >= graph_.points.size()) {
    robot.arrival_point = -1;
    robot.arrival_area.clear();
    robot.arrival_reach.clear();
    return;
  }
  if (robot.arrival_point == goal_point && same_area(robot.arrival_area, area)) return;
  robot.arrival_point = goal_point;
  robot.arrival_area = area;
  places_under(area, robot.type, &robot.arrival_reach);
}

bool TrafficManager::holds_arrival(int robot_id) const {
  const auto it = robots_.find(robot_id);
  return it != robots_.end() && it->second.arrival_held;
}

geometry::Polygon TrafficManager::turn_area(int robot_id) const {
  const auto it = robots_.find(robot_id);
  if (it == robots_.end() || it->second.frozen) return {};
  const Robot& robot = it->second;
  if (robot.arrival_held) return robot.arrival_area;
  return robot.reach_of_turn ? robot.body_polygon : geometry::Polygon{};
}

void TrafficManager::leave_arrival(Robot& robot) {
  if (robot.arrival_held) {
    robot.body_reach = std::move(robot.arrival_reach);
    robot.body_polygon = robot.arrival_area;
    robot.reach_of_turn = true;
  }
  robot.arrival_point = -1;
  robot.arrival_held = false;
  robot.arrival_area.clear();
  robot.arrival_reach.clear();
}

bool TrafficManager::arrival_pending(const Robot& robot, int index) const {
  return index + 1 == static_cast<int>(robot.route.size()) && !robot.arrival_held &&
         robot.arrival_point == robot.route.back() && !robot.arrival_reach.empty();
}

std::vector<int> TrafficManager::arrival_blockers(const Robot& robot) const {
  // A robot in the area by what it holds: a standing one by its body alone (its places' regions
  // reach a body length beyond it), one on a route by its places' regions, one turning in or
  // backing out by its own area. Robots waiting for this one stay where they are: queued up behind
  // it, their grants end short of its places.
  std::vector<int> out;
  const auto& area = robot.arrival_area;
  for (const auto& [id, other] : robots_) {
    // Its partner stands where the two work together (set_partners): the picker arrives beside
    // the transporter's pallet.
    if (id == robot.id || partnered(robot.id, id)) continue;
    const bool waits_for_it =
        other.wait_since >= 0.0 && std::binary_search(other.blocked_by.begin(), other.blocked_by.end(), robot.id);
    if (waits_for_it && !other.frozen) continue;
    bool in_way = other.arrival_held && geometry::convex_polygons_overlap(other.arrival_area, area);
    if (!other.body_reach.empty() && !other.body_polygon.empty()) {
      in_way = in_way || geometry::convex_polygons_overlap(other.body_polygon, area);
    }
    if (!in_way && !other.frozen) {
      const auto& near = robot.arrival_reach[static_cast<std::size_t>(other.type)];
      for (int p : held_places(id)) {
        if (!under_body(other, p) && std::binary_search(near.begin(), near.end(), p)) {
          in_way = true;
          break;
        }
      }
    }
    if (in_way) out.push_back(id);
  }
  sort_unique(out);
  return out;
}

void TrafficManager::keep_clear(int robot_id, const geometry::Polygon& area) {
  const auto it = robots_.find(robot_id);
  if (area.size() < 3 || it == robots_.end() || !it->second.frozen) {
    ways_out_.erase(robot_id);
    return;
  }
  auto known = ways_out_.find(robot_id);
  if (known != ways_out_.end() && same_area(known->second.area, area)) return;
  WayOut way_out{area, {}};
  places_under(area, it->second.type, &way_out.reach);
  for (auto& places : way_out.reach) sort_unique(places);
  ways_out_[robot_id] = std::move(way_out);
}

bool TrafficManager::stop_kept_clear(const Robot& robot, int place) const {
  const auto type = static_cast<std::size_t>(robot.type);
  return std::any_of(ways_out_.begin(), ways_out_.end(), [&](const auto& entry) {
    const auto& [id, way_out] = entry;
    return id != robot.id && type < way_out.reach.size() &&
           std::binary_search(way_out.reach[type].begin(), way_out.reach[type].end(), place);
  });
}

}  // namespace fleet::traffic
