// The way off the road into the goal: what a forklift sweeps turning off its lane into a place
// beside it, held by traffic with the route's last point.
#include <cmath>
#include <numbers>
#include <optional>

#include "robot/forklift/forklift.hpp"

namespace fleet::robot {

using geometry::Vec2;

std::vector<Vec2> Forklift::arrival_sweep(std::optional<Vec2> place) const {
  constexpr double kBesideTheRoad = 0.2;  // metres off the road's last point
  constexpr double kSample = 0.25;        // metres between bodies along the path
  constexpr int kTurnSamples = 16;        // headings of a turn on the spot
  std::vector<Vec2> corners;
  const std::vector<Vec2>& path = nav_.follower().path();
  if (!config_.traffic || !nav_.follower().on_road() || path.size() < 2) return corners;
  const auto add = [&](Vec2 at, double yaw) {
    const geometry::Polygon body = geometry::footprint_polygon({at.x, at.y, yaw}, footprint());
    corners.insert(corners.end(), body.begin(), body.end());
  };
  // The robot turns towards its goal about where the road ends, to the goal's heading where the
  // path ends and in the loading area, the follower cutting the corners between: a whole turn at
  // each bounds them, and their hull the straight moves between.
  const auto turn_at = [&](Vec2 at) {
    for (int i = 0; i < kTurnSamples; ++i) add(at, 2.0 * std::numbers::pi * i / kTurnSamples);
  };
  const double road_end = nav_.follower().road_end();
  double along = 0.0;
  bool started = false;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vec2 a = path[i - 1];
    const Vec2 b = path[i];
    const double length = geometry::distance(a, b);
    if (length < 1e-9) continue;
    const double heading = std::atan2(b.y - a.y, b.x - a.x);
    for (double s = std::max(0.0, road_end - along); s < length; s += kSample) {
      const Vec2 at = a + (s / length) * (b - a);
      if (!started) {
        turn_at(at);
        started = true;
      }
      add(at, heading);
    }
    along += length;
  }
  // A pick or a drop goes on from the path's end into the loading area.
  const double beyond = std::max(0.0, along - road_end) + (place ? geometry::distance(path.back(), *place) : 0.0);
  if (beyond < kBesideTheRoad) return {};
  turn_at(path.back());
  if (place) {
    turn_at(*place);
    // Having set a load down it backs its forks out of it, further from the place than the path
    // ends, and turns there onto its next route: a long vehicle leaving a rack place sweeps the
    // far lane of the aisle (pallet_place's back_out_distance).
    const Vec2 away = path.back() - *place;
    const double length = std::hypot(away.x, away.y);
    if (length > 1e-9) turn_at(path.back() + (config_.task.place.back_out_distance / length) * away);
  }
  return corners;
}

std::optional<Vec2> Forklift::place_of(task::PlanPurpose purpose) const {
  const auto& order = executor_.order();
  if (!order) return std::nullopt;
  if (purpose == task::PlanPurpose::kToPick) return order->pick_area.position();
  if (purpose == task::PlanPurpose::kToDrop) return order->drop_area.position();
  return std::nullopt;
}

}  // namespace fleet::robot
