#pragma once

#include <array>

namespace fleet::sim {

/// A body-frame velocity command or measurement: x forward, y left, yaw rate counter-clockwise.
struct BodyTwist {
  double vx = 0.0;     ///< m/s
  double vy = 0.0;     ///< m/s
  double omega = 0.0;  ///< rad/s
};

/// Wheel angular velocities in rad/s, numbered as in [Forklift thesis, Fig. 6.1 / eq. 6.1].
using WheelSpeeds = std::array<double, 4>;

/// Geometry and actuator limits of a four-wheel mecanum base. Defaults match a 15 x 25 cm
/// table-top forklift driven by continuous-rotation servos.
struct MecanumParams {
  double wheel_radius = 0.03;     ///< r, metres
  double half_wheelbase = 0.08;   ///< l_x: wheel centre to body centre along x, metres
  double half_track = 0.06;       ///< l_y: wheel centre to body centre along y, metres
  double max_wheel_speed = 10.0;  ///< servo limit, rad/s (about 95 rpm)
};

/// Body speed limits implied by the servo limit ("speed limits ... can be calculated from the speed
/// limits of the servo motors" [Forklift thesis, section 6.1]).
struct BodyLimits {
  double max_linear = 0.0;   ///< pure translation along x or y with every wheel at the limit, m/s
  double max_angular = 0.0;  ///< pure rotation with every wheel at the limit, rad/s
};

class MecanumKinematics {
 public:
  explicit MecanumKinematics(const MecanumParams& params = {});

  /// Wheel speeds for a body twist [Forklift thesis, eq. 6.1] (no slip).
  WheelSpeeds inverse(const BodyTwist& twist) const;

  /// Body twist from wheel speeds: the r/4 pseudo-inverse of eq. 6.1 ([Picker thesis, eq. 3.7], written
  /// with the wheel numbering of [Forklift thesis, eq. 6.1]).
  BodyTwist forward(const WheelSpeeds& wheels) const;

  /// Scales all four wheel speeds by one factor so none exceeds the servo limit. Scaling them
  /// together keeps the direction of motion and the curvature, which clipping each wheel would not.
  WheelSpeeds saturate(const WheelSpeeds& wheels) const;

  /// The command that is actually achievable: inverse, saturate, forward.
  BodyTwist limit(const BodyTwist& twist) const;

  BodyLimits limits() const;
  const MecanumParams& params() const { return params_; }

 private:
  MecanumParams params_;
};

}  // namespace fleet::sim
