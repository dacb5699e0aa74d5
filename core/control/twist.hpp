#pragma once

#include <cmath>

#include "geometry/pose.hpp"

namespace fleet::control {

/// A velocity command in the body frame, the inputs of [Forklift thesis, eq. 6.1]: vx forward, vy left, omega
/// counter-clockwise. A mecanum base turns it into wheel speeds; the path follower keeps vy = 0.
struct BodyTwist {
  double vx = 0.0;     ///< m/s
  double vy = 0.0;     ///< m/s
  double omega = 0.0;  ///< rad/s

  friend bool operator==(const BodyTwist&, const BodyTwist&) = default;
};

/// Moves `pose` by a body twist held constant for `dt` seconds, integrating exactly along the
/// arc (a plain Euler step would bias every turn outwards). Used by tests and by the fallback
/// kinematic body of the evaluation tool.
inline geometry::Pose2 integrate_twist(const geometry::Pose2& pose, const BodyTwist& twist, double dt) {
  const double dth = twist.omega * dt;
  double bx = 0.0;
  double by = 0.0;
  if (std::abs(dth) < 1e-9) {
    bx = twist.vx * dt;
    by = twist.vy * dt;
  } else {
    // Body-frame displacement of a constant (vx, vy, omega) over dt.
    const double s = std::sin(dth) / twist.omega;
    const double c = (1.0 - std::cos(dth)) / twist.omega;
    bx = s * twist.vx - c * twist.vy;
    by = c * twist.vx + s * twist.vy;
  }
  const geometry::Vec2 p = geometry::body_to_map(pose, {bx, by});
  return {p.x, p.y, geometry::normalize_angle(pose.yaw + dth)};
}

}  // namespace fleet::control
