#include "control/tricycle_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace fleet::control {

TricycleDrive tricycle_drive_for(const vehicle::VehicleProfile& profile) {
  TricycleDrive d;
  d.pursuit.max_speed = profile.max_speed;
  d.pursuit.acceleration = std::min(profile.max_acceleration, d.body.max_wheel_acceleration);
  if (profile.wheelbase > 0.0) d.body.geometry.wheelbase = profile.wheelbase;
  // The fork tips are the footprint's back end: the rear axle stands that far ahead of them.
  const geometry::Footprint extent = profile.extent();
  if (profile.rear_axle_x < 0.0 && profile.rear_axle_x > -extent.length / 2.0) {
    d.body.geometry.rear_overhang = profile.rear_axle_x + extent.length / 2.0;
  }
  // +-pi/2 is the pivot [Stacker thesis, section 5.2]; a profile's rounded 1.5708 means it.
  if (profile.max_steering_angle > 0.0) {
    d.body.max_steer_angle = std::min(profile.max_steering_angle, std::numbers::pi / 2);
  }
  return d;
}

std::vector<geometry::Pose2> roll_forward(sim::Tricycle ghost, const std::vector<geometry::Vec2>& path,
                                          const TricyclePursuitParams& pursuit, double wheelbase, double period,
                                          double distance) {
  std::vector<geometry::Pose2> poses;
  if (!(period > 0.0) || !(pursuit.max_speed > 0.0)) return poses;
  // A bound on the steps: three times the distance at top speed, for a pivot, which turns the
  // body without moving the rear axle.
  const int max_steps = static_cast<int>(std::ceil(3.0 * distance / (pursuit.max_speed * period)));
  double travelled = 0.0;
  for (int k = 0; k < max_steps && travelled < distance; ++k) {
    const TricyclePursuitOutput out = pursue(ghost.pose(), path, std::numeric_limits<double>::infinity(),
                                             ghost.state().theta_steer, pursuit, wheelbase);
    if (out.arrived) break;
    const geometry::Vec2 before = ghost.pose().position();
    ghost.step(out.command, period);
    poses.push_back(ghost.pose());
    travelled += geometry::distance(before, ghost.pose().position());
  }
  return poses;
}

std::vector<geometry::Pose2> drive_along(const TricycleDrive& drive, const std::vector<geometry::Vec2>& path,
                                         bool at_speed) {
  if (path.size() < 2) return {};
  const geometry::Vec2 first = path[1] - path[0];
  const geometry::Pose2 start{path[0].x, path[0].y, std::atan2(first.y, first.x)};
  double length = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) length += geometry::distance(path[i], path[i + 1]);
  sim::Tricycle ghost(drive.body, start);
  if (at_speed) {
    // Long enough for the wheel's lag and acceleration to settle, then put back at the start.
    const double settle =
        drive.pursuit.max_speed / drive.body.max_wheel_acceleration + 10.0 * drive.body.drive_time_constant;
    ghost.step({drive.pursuit.max_speed, 0.0}, settle);
    ghost.move_to(start);
  }
  std::vector<geometry::Pose2> poses =
      roll_forward(ghost, path, drive.pursuit, drive.body.geometry.wheelbase, drive.control_period, length);
  const double c = drive.centre_offset();
  for (geometry::Pose2& p : poses) p = geometry::body_pose_to_map(p, {c, 0.0, 0.0});
  return poses;
}

}  // namespace fleet::control
