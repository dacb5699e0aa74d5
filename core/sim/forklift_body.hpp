#pragma once

#include <random>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "sim/mecanum.hpp"

namespace fleet::sim {

struct ForkliftParams {
  MecanumParams mecanum;
  geometry::Footprint footprint{0.25, 0.16};  ///< about 15-18 x 25 cm [Forklift thesis]
  /// First-order wheel response, [Picker thesis, eq. 4.29] (tau = 0.02 s after the thesis's experiments).
  double wheel_time_constant = 0.02;
  /// Relative ground-speed error of each wheel (roller slip), a slowly varying Gauss-Markov
  /// process per wheel. 0 turns slip off. It makes commanded and wheel-encoder velocities differ
  /// from the true motion, as they do on a real floor.
  double slip_std = 0.03;
  double slip_correlation_time = 1.0;  ///< seconds
  /// Longest internal integration step; step() subdivides longer calls so that the wheel lag and
  /// curved motion are integrated accurately whatever rate the caller runs at.
  double max_substep = 0.002;  ///< seconds
};

/// The simulated truth of one mecanum forklift. The software under test only ever sees it
/// through sensors; the simulation, collision checks and the web view's truth layer read pose().
///
/// Not thread-safe: one owner steps it.
class ForkliftBody {
 public:
  /// `rng` drives the slip noise only; pass a seeded engine for reproducible runs.
  ForkliftBody(const ForkliftParams& params, const geometry::Pose2& start, std::mt19937_64 rng);

  /// Applies the body twist `cmd` (held constant) for `dt` seconds: inverse kinematics, servo
  /// saturation, first-order wheel lag, slip, forward kinematics, exact integration of the pose.
  /// Non-finite commands are treated as a stop; dt <= 0 or non-finite does nothing.
  void step(const BodyTwist& cmd, double dt);

  /// Puts the body at `pose`, at rest.
  void reset(const geometry::Pose2& pose);

  const geometry::Pose2& pose() const { return pose_; }
  /// The true body twist at the end of the last step, including slip (what a gyro senses).
  const BodyTwist& twist() const { return twist_; }
  /// What the wheels actually turn at (what an encoder sees), rad/s.
  const WheelSpeeds& wheel_speeds() const { return wheels_; }
  /// The last command after servo saturation, as the drive accepted it.
  const BodyTwist& command() const { return command_; }
  /// Map-frame corners of the footprint at the true pose.
  geometry::Polygon footprint_polygon(double margin = 0.0) const;

  const MecanumKinematics& kinematics() const { return kinematics_; }
  const ForkliftParams& params() const { return params_; }

 private:
  void substep(const WheelSpeeds& target, double dt);

  ForkliftParams params_;
  MecanumKinematics kinematics_;
  std::mt19937_64 rng_;
  geometry::Pose2 pose_;
  BodyTwist twist_;
  BodyTwist command_;
  WheelSpeeds wheels_{};
  WheelSpeeds slip_{};
};

}  // namespace fleet::sim
