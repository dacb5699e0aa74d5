#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "control/twist.hpp"
#include "geometry/pose.hpp"

namespace fleet::control {

/// Settings of the path follower, fixed per instance. The first block is the thesis's controller
/// [Forklift thesis, section 6.1]; the second switches on the extensions, each off by default so the
/// thesis's behaviour is what one gets unless asked otherwise.
struct FollowerParams {
  // --- [Forklift thesis, section 6.1] ---
  double v_max = 0.20;              ///< forward speed at omega = 0, m/s
  double omega_max = 2.0;           ///< angular speed limit, rad/s; forward speed is 0 there (Forklift thesis, eq. 6.2)
  double lookahead = 0.10;          ///< minimum distance to the target point on the path, metres
  double kp = 4.0;                  ///< PID on the turning error beta (Forklift thesis, eq. 6.3), 1/s
  double ki = 0.0;                  ///< 1/s^2
  double kd = 0.05;                 ///< dimensionless
  double integral_limit = 0.3;      ///< anti-windup clamp on the integral of beta, rad s
  double goal_tolerance = 0.01;     ///< along-track distance to the end that counts as arrived, m
  double heading_tolerance = 0.02;  ///< final heading error that ends the turn in place, rad
  double rotate_gain = 3.0;         ///< turn-in-place gain on the final heading error, 1/s
  double rotate_omega_min = 0.15;   ///< slowest useful turn in place, rad/s (motor deadband)

  // --- beyond the thesis: switchable ---
  /// Target moves continuously along the path (interpolated at `lookahead` arc length ahead of
  /// the robot's projection) instead of jumping from one path point to the next; removes the
  /// command jumps the thesis reports when the target switches (Forklift thesis, section 6.1, Fig. 6.4b).
  bool smooth_lookahead = false;
  /// Slow down where the arc to the target is tight (Nav2 Regulated Pure Pursuit).
  bool regulate_curvature = false;
  double regulate_min_radius = 0.40;  ///< below this turning radius speed scales with radius, m
  /// Slow down near obstacles (Nav2 RPP's proximity regulation); the distance comes per step.
  bool regulate_obstacles = false;
  double obstacle_slow_distance = 0.30;  ///< start slowing at this clearance, m
  double obstacle_stop_distance = 0.06;  ///< stop at this clearance, m
  double regulated_min_speed = 0.03;     ///< regulation never asks for less than this (unless stopping), m/s
  /// Bound the change of vx and omega per step and brake early enough to stop at the end.
  bool limit_acceleration = false;
  double max_linear_accel = 0.5;   ///< m/s^2
  double max_angular_accel = 6.0;  ///< rad/s^2
  /// A path whose first leg (up to a cusp) is shorter than this, and longer than
  /// reverse_legs_up_to, starts on its second leg: a robot standing a few centimetres past the
  /// road point its route begins at does not turn round to touch it and turn back, sweeping its
  /// body through the room beside it, m.
  double shortest_first_leg = 0.0;
  /// A path whose final heading points back along its last straight stretch is driven backwards
  /// over at most this much of that stretch, when set_path is asked to back in: the robot turns
  /// where the stretch starts (on the road) instead of at its end (in a parking stall between
  /// others). 0 never backs in, m.
  double back_in_up_to = 0.0;
  /// A leg (between cusps) no longer than this whose end lies behind the robot as the leg starts
  /// is driven backwards instead of turning round at both of its ends: a robot that traffic
  /// pushes back a few places along a lane and then sends on again keeps facing the way it goes
  /// on, and sweeps no turn into the robots in front of and behind it. For a base that drives
  /// either way; 0 turns round for every leg, m.
  double reverse_legs_up_to = 0.0;

  /// The settings with every extension switched on.
  static FollowerParams regulated();
};

/// What the follower is doing.
enum class FollowerStatus {
  kIdle,      ///< no path or pose target
  kTracking,  ///< driving towards the path's end or the target point
  kAligning,  ///< at the end, turning in place to the final heading
  kArrived,   ///< at the end with the final heading: commands are zero
};

const char* to_string(FollowerStatus status);

/// Per-step inputs.
struct FollowerInput {
  geometry::Pose2 pose;  ///< localization estimate
  double dt = 0.0;       ///< seconds since the previous step (0 on the first)
  /// Clearance to the nearest obstacle ahead, metres; infinity when none is known.
  double obstacle_distance = std::numeric_limits<double>::infinity();
  /// Metres the robot may drive along the path from where it is (the end of a traffic grant);
  /// infinity when the whole path is its to drive. At a cusp the next leg starts only once this
  /// reaches past it.
  double granted_distance = std::numeric_limits<double>::infinity();
};

/// Diagnostics of one step, for plots and tests.
struct FollowerDebug {
  geometry::Vec2 target;         ///< the lookahead target in use
  double beta = 0.0;             ///< turning error of eq. 6.3, rad
  double cross_track = 0.0;      ///< signed distance to the path, metres, left positive
  double remaining = 0.0;        ///< along-track distance to the end, metres
  std::size_t target_index = 0;  ///< path index of the target (seed mode) or its segment
};

/// Forward speed of eq. 6.2 for an angular speed: v_max at omega = 0 falling linearly to 0 at
/// |omega| = omega_max. The seed prints v_x = v_max (omega_max - |omega|), which is this law up to
/// the factor 1/omega_max that makes the units and the stated end points agree.
double speed_law(double omega, double v_max, double omega_max);

/// Path follower [Forklift thesis, section 6.1, Fig. 6.3]: a target point on the path at least
/// `lookahead` away, turning error beta = h - atan2(yd - y, xd - x) (Forklift thesis, eq. 6.3) through a PID to
/// omega, clamped to omega_max, forward speed from eq. 6.2, differential mode (vy = 0). At the
/// end it turns in place until the heading error is near zero, then stops.
///
/// Not thread-safe; one instance per robot, stepped from one loop.
class PathFollower {
 public:
  explicit PathFollower(FollowerParams params = {});

  const FollowerParams& params() const { return params_; }

  /// Follows `path` (at least one pose). Headings of the inner poses are ignored; the last
  /// pose's heading is the one to finish with. A path that turns back on itself is split at the
  /// cusp: the robot drives to the cusp, turns in place and goes on; a first leg shorter than
  /// `shortest_first_leg` is skipped. With `may_back_in`, a final heading that points back along
  /// the last straight stretch makes the stretch's last `back_in_up_to` metres a leg of its own,
  /// driven backwards. Resets the PID and the progress along the path.
  void set_path(std::vector<geometry::Pose2> path, bool may_back_in = false);

  /// Pose-target mode (Forklift thesis, section 6.1: "path with single point and heading"): drive to the point,
  /// then turn to the heading.
  void set_pose_target(const geometry::Pose2& target);

  /// Forgets the path; commands become zero.
  void clear();

  /// One control step. Returns the body twist to apply until the next step.
  BodyTwist step(const FollowerInput& input);

  /// Metres along the path from its start to where the leg being followed begins (0 on the
  /// first): on a path that passes over the same ground twice, which pass the robot is on.
  double leg_start_s() const { return path_.empty() ? 0.0 : cum_[leg_start()]; }
  /// The path's length, metres.
  double length() const { return cum_.empty() ? 0.0 : cum_.back(); }

  FollowerStatus status() const { return status_; }
  bool arrived() const { return status_ == FollowerStatus::kArrived; }
  const FollowerDebug& debug() const { return debug_; }
  const std::vector<geometry::Pose2>& path() const { return path_; }

 private:
  struct Projection {
    std::size_t segment = 0;  ///< path_[segment] -> path_[segment + 1]
    double t = 0.0;           ///< fraction along it, may exceed 1 on the last segment
    double s = 0.0;           ///< arc length from the start
    double cross = 0.0;       ///< signed lateral offset, left positive
  };

  Projection project(geometry::Vec2 p);
  geometry::Vec2 point_at(double s) const;
  geometry::Vec2 seed_target(geometry::Vec2 p, std::size_t& index);
  /// The lookahead target from `s` metres along the path when the robot may drive `granted`
  /// metres of it: on the path, or straight on from the grant's end when that is nearer.
  geometry::Vec2 granted_target(double s, double granted) const;
  BodyTwist limit_turn(BodyTwist cmd, double dt);
  void reset_controller();
  void split_off_back_in();
  /// Whether the leg being followed is driven backwards: backed in, or short and behind the robot
  /// at `pose` when it starts (chosen once per leg).
  bool drives_backwards(const geometry::Pose2& pose);
  std::size_t leg_end() const { return leg_ends_[leg_]; }
  std::size_t leg_start() const { return leg_ == 0 ? 0 : leg_ends_[leg_ - 1]; }

  FollowerParams params_;
  std::vector<geometry::Pose2> path_;
  std::vector<double> cum_;            ///< arc length at each path point
  std::vector<std::size_t> leg_ends_;  ///< path indices of the cusps, then the last point
  std::size_t leg_ = 0;                ///< index into leg_ends_ of the leg being followed
  std::size_t backwards_leg_ = 0;      ///< the leg backed in; leg_ends_.size() when none
  /// The leg whose direction was last chosen (reverse_legs_up_to) and whether it is reversed.
  std::size_t chosen_leg_ = 0;
  bool leg_chosen_ = false;
  bool leg_reversed_ = false;
  bool pose_target_ = false;
  FollowerStatus status_ = FollowerStatus::kIdle;
  std::size_t progress_ = 0;      ///< segment the robot was last projected onto (monotonic)
  std::size_t target_index_ = 0;  ///< seed mode: last target point index (monotonic)
  double integral_ = 0.0;
  double prev_beta_ = 0.0;
  bool have_prev_ = false;
  BodyTwist last_cmd_;
  FollowerDebug debug_;
};

}  // namespace fleet::control
