// The way out of a dock or a bay onto the road: what the stacker sweeps turning onto its lane,
// asked of traffic before it sets off, as the docking asks for its manoeuvre's area.
#include <cmath>

#include "robot/stacker/stacker.hpp"

namespace fleet::robot {

using geometry::Pose2;
using geometry::Vec2;

std::vector<Vec2> Stacker::way_out_area() const {
  // Past the road's first point the route's own places (with the bodies traffic tracks along
  // curves) cover the body; this far beyond it the turn onto the lane is done.
  constexpr double kBeyondRoadStart = 1.0;  // metres of path
  constexpr double kSample = 0.25;          // metres between bodies along the path
  constexpr int kPivotSamples = 8;
  const std::vector<Vec2>& path = nav_.follower().path();
  std::vector<Vec2> corners;
  if (path.size() < 2) return corners;
  const auto add = [&](Vec2 rear, double yaw) { add_swept_body(corners, rear, yaw); };
  // Where it stands, and turning about the rear axle towards the path, as the pursuit does when
  // the path leads off to the side or behind.
  const Pose2 here = estimate_;
  const double first = std::atan2(path[1].y - path[0].y, path[1].x - path[0].x);
  const double turn = geometry::angle_diff(first, here.yaw);
  for (int i = 0; i <= kPivotSamples; ++i) add(here.position(), here.yaw + turn * i / kPivotSamples);
  // Then the rear axle along the path, the body along its heading.
  const double until = nav_.follower().road_start() + kBeyondRoadStart;
  double along = 0.0;
  for (std::size_t i = 1; i < path.size() && along < until; ++i) {
    const Vec2 a = path[i - 1];
    const Vec2 b = path[i];
    const double length = geometry::distance(a, b);
    if (length < 1e-9) continue;
    const double heading = std::atan2(b.y - a.y, b.x - a.x);
    for (double s = 0.0; s < length && along + s < until; s += kSample) add(a + (s / length) * (b - a), heading);
    along += length;
    add(b, heading);
  }
  return corners;
}

}  // namespace fleet::robot
