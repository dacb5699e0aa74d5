#pragma once

#include "geometry/pose.hpp"
#include "sim/encoders.hpp"
#include "sim/forklift_body.hpp"
#include "sim/mecanum.hpp"

namespace fleet::sim {

/// Speeds of the picker's base [Picker thesis, sections 3.1.1 and 4.2.9].
struct SummitXlsSpeeds {
  static constexpr double kTop = 3.0;        ///< top speed on every axis, m/s [Picker thesis, section 3.1.1]
  static constexpr double kTest = 0.3;       ///< speed of the navigation tests, m/s
                                             ///< [Picker thesis, section 4.3.2.1, Fig. 4.27]
  static constexpr double kMaxTested = 1.0;  ///< highest speed of the marker and controller tests, m/s
                                             ///< [Picker thesis, sections 4.2.9, 4.3.2]
};

/// The picker's mecanum base, a Robotnik Summit-XLS [Picker thesis, section 3.1.1]: 0.65 x 0.50 m including the
/// wheels, 3 m/s top speed, rollers at γ = π/4, −π/4, π/4, −π/4 [Picker thesis, eq. 3.5-3.6], which is the wheel-speed
/// matrix of MecanumKinematics with l_x = a, l_y = b (the seed numbers the wheels front-right, front-left, rear-left,
/// rear-right; MecanumKinematics front-left, front-right, rear-left, rear-right: the same rows in another order).
///
/// The seed gives no r, a, b. Chosen: r = 0.127 m (the 254 mm wheels), b = 0.20 m (half of the 0.50 m width less
/// half a 0.10 m wheel), a = 0.195 m (half of the 0.65 m length less a wheel radius: a + r must stay within 0.325 m).
/// Wheel response: first order with τ = 0.075 s, so that a 0.3 m/s step settles within ±2 % in ln(50)·τ ≈ 0.29 s,
/// the "almost 0.3 seconds" measured on the robot [Picker thesis, section 4.3.2.1, Fig. 4.27]. The seed's plant model
/// for the aisle laws says τ = 0.02 [Picker thesis, eq. 4.29], which settles in 0.08 s: the two conflict; the aisle
/// tests set 0.02 themselves. Roller slip: the ForkliftParams default (3 %).
ForkliftParams summit_xls_body_params();

/// The Summit-XLS wheel encoders [Picker thesis, section 3.1.1: "the wheels are fitted with encoders to give precise
/// odometry"]: on. The seed gives no resolution or rate; chosen: 4096 ticks per wheel turn, read at 50 Hz, 0.01 rad/s
/// noise.
EncoderParams summit_xls_encoder_params();

/// Dead reckoning from wheel speeds by the forward kinematics [Picker thesis, eq. 3.7] (the r/4 pseudo-inverse of
/// eq. 3.5), each reading held over its period and integrated exactly along the arc.
class WheelOdometry {
 public:
  WheelOdometry(const MecanumParams& params, const geometry::Pose2& start);

  /// Moves the estimate by the wheel speeds `wheels` (rad/s, e.g. WheelEncoders::measure) held over `dt` seconds.
  /// Returns the body twist of eq. 3.7. Non-finite readings or dt <= 0 leave the pose unchanged.
  BodyTwist update(const WheelSpeeds& wheels, double dt);

  const geometry::Pose2& pose() const { return pose_; }
  void reset(const geometry::Pose2& pose) { pose_ = pose; }

 private:
  MecanumKinematics kinematics_;
  geometry::Pose2 pose_;
};

}  // namespace fleet::sim
