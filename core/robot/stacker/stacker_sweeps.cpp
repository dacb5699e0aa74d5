#include "robot/stacker/stacker_sweeps.hpp"

#include <algorithm>
#include <cmath>

#include "robot/stacker/stacker.hpp"

namespace fleet::robot {

using geometry::Pose2;
using geometry::Vec2;

Vec2 heading_of(double yaw) {
  return {std::cos(yaw), std::sin(yaw)};
}

Pose2 rear_axle_at(const Pose2& centre, const sim::TricycleGeometry& geometry) {
  const Vec2 rear = centre.position() - geometry.centre_x() * heading_of(centre.yaw);
  return {rear.x, rear.y, centre.yaw};
}

double carried_offset(const control::DockingParams& docking, const sim::TricycleGeometry& geometry) {
  return geometry.fork_tip_x() + docking.pocket_depth - 0.5 * docking.pallet.depth;
}

std::vector<Vec2> with_mirror_image(std::vector<Vec2> corners, const Pose2& axis) {
  const Vec2 along = heading_of(axis.yaw);
  const std::size_t n = corners.size();
  corners.reserve(2 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 d = corners[i] - axis.position();
    const Vec2 on_axis = (d.x * along.x + d.y * along.y) * along;
    corners.push_back(axis.position() + 2.0 * on_axis - d);
  }
  return corners;
}

StackerSweeps::StackerSweeps(const StackerConfig& config)
    : config_(config), footprint_{config.body.geometry.length, config.body.geometry.width} {}

void StackerSweeps::add_body(std::vector<Vec2>& corners, Vec2 rear, double yaw) const {
  const Vec2 centre = rear + config_.body.geometry.centre_x() * heading_of(yaw);
  const auto body = geometry::footprint_polygon({centre.x, centre.y, yaw}, footprint_, config_.work_area_margin);
  corners.insert(corners.end(), body.begin(), body.end());
}

std::vector<Vec2> StackerSweeps::docking(const control::DockingLaw& law, const Pose2& here, const Pose2& prior) const {
  const sim::TricycleGeometry& g = config_.body.geometry;
  std::vector<Vec2> corners;
  const auto add = [&](Vec2 rear, double yaw) { add_body(corners, rear, yaw); };
  // Not where it stands: its body holds that already, and the robots queued up behind it touch it.
  // The run starts with the rear axle short of target 2 and never backs past it.
  const auto [target1, target2] = law.targets();
  add(target1, here.yaw);
  // The pivot about the rear axle at target 2, from the heading along the row to the docked one.
  const double turn = geometry::angle_diff(prior.yaw, here.yaw);
  constexpr int kPivotSamples = 8;
  for (int i = 0; i <= kPivotSamples; ++i) add(target2, here.yaw + turn * i / kPivotSamples);
  // Realigning, it drives out along the axis to the realignment stand-off; docked, it stands in
  // the place.
  const control::DockingParams& d = config_.docking;
  const Vec2 face = prior.position() + 0.5 * d.pallet.depth * heading_of(prior.yaw);
  add(face + d.realign_standoff * heading_of(prior.yaw), prior.yaw);
  add(prior.position() - carried_offset(d, g) * heading_of(prior.yaw), prior.yaw);
  return corners;
}

std::vector<Vec2> StackerSweeps::arrival(const std::vector<Vec2>& path, const control::DockingParams& params,
                                         const Pose2& prior) const {
  if (path.size() < 2) return {};
  // The rear axle ends the route at its last point, heading along its last leg.
  const Vec2 end = path.back();
  const Vec2 before = path[path.size() - 2];
  const Pose2 there{end.x, end.y, std::atan2(end.y - before.y, end.x - before.x)};
  const control::DockingLaw law(params, prior, there);
  std::vector<Vec2> corners = docking(law, there, prior);
  add_body(corners, there.position(), there.yaw);
  return corners;
}

std::vector<Vec2> StackerSweeps::way_out(const std::vector<Vec2>& path, const Pose2& here, double road_start) const {
  // Past the road's first point the route's own places (with the bodies traffic tracks along
  // curves) cover the body; this far beyond it the turn onto the lane is done.
  constexpr double kBeyondRoadStart = 1.0;  // metres of path
  constexpr double kSample = 0.25;          // metres between bodies along the path
  constexpr int kPivotSamples = 8;
  std::vector<Vec2> corners;
  if (path.size() < 2) return corners;
  const auto add = [&](Vec2 rear, double yaw) { add_body(corners, rear, yaw); };
  // Where it stands, and turning about the rear axle towards the path, as the pursuit does when
  // the path leads off to the side or behind.
  const double first = std::atan2(path[1].y - path[0].y, path[1].x - path[0].x);
  const double turn = geometry::angle_diff(first, here.yaw);
  for (int i = 0; i <= kPivotSamples; ++i) add(here.position(), here.yaw + turn * i / kPivotSamples);
  // Then the rear axle along the path, the body along its heading.
  const double until = road_start + kBeyondRoadStart;
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

std::vector<Vec2> StackerSweeps::straight_back(const Pose2& here, Vec2 to, double yaw) const {
  std::vector<Vec2> corners;
  const double length = geometry::distance(here.position(), to);
  constexpr double kSample = 0.25;  // metres between bodies along the line
  const int samples = std::max(1, static_cast<int>(std::ceil(length / kSample)));
  for (int i = 1; i <= samples; ++i) {
    const double t = std::min(1.0, i * kSample / std::max(length, 1e-9));
    add_body(corners, here.position() + t * (to - here.position()), yaw);
  }
  return corners;
}

Vec2 StackerSweeps::approach_of(const Pose2& prior) const {
  const control::DockingParams& d = config_.docking;
  const double out = 0.5 * d.pallet.depth + d.target2_standoff + d.target1_extra_standoff;
  return prior.position() + out * heading_of(prior.yaw);
}

}  // namespace fleet::robot
