#pragma once

#include <array>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"

namespace fleet::sim {

/// Dimensions of the BT Staxio SPE200DN stacker as modified for docking [Stacker thesis, sections 4.2.3-4.2.4]:
/// 1.700 m x 0.748 m, one front wheel that drives and steers, two passive load wheels near the fork tips. The
/// body frame has its origin at the rear-axle midpoint (the control reference and the pivot point at
/// theta_steer = +-pi/2 [Stacker thesis, section 5.2]), x towards the drive wheel, y to the left. The forks point
/// backwards (-x): the stacker docks in reverse.
///
/// The thesis gives neither the wheelbase nor the wheel radius. The values below fit the truck: a 1.15 m fork
/// (a common length for EPAL work) behind a 0.55 m chassis makes the 1.700 m; the load wheels sit 0.10 m short of
/// the fork tips, so the rear axle is 0.10 m ahead of them; the drive wheel sits under the chassis 0.30 m behind
/// the front, hence L = 1.30 m.
struct TricycleGeometry {
  double length = 1.700;        ///< overall, fork tips to front bumper, metres
  double width = 0.748;         ///< chassis width, metres
  double wheelbase = 1.30;      ///< L: rear axle to drive wheel, metres (not in the thesis; see above)
  double rear_overhang = 0.10;  ///< fork tips behind the rear axle, metres
  double fork_length = 1.15;    ///< fork tips to the chassis back face, metres
  double fork_width = 0.17;     ///< one fork, metres
  double fork_spacing = 0.38;   ///< fork centre to fork centre, metres (EPAL pocket centres are 0.3725 m apart)
  double wheel_radius = 0.115;  ///< drive wheel, metres [Stacker thesis, eq. 5.1] (not in the thesis)

  double front_x() const { return length - rear_overhang; }
  double fork_tip_x() const { return -rear_overhang; }
  double chassis_back_x() const { return -rear_overhang + fork_length; }
  double drive_wheel_x() const { return wheelbase; }
  /// The footprint's centre, ahead of the rear axle.
  double centre_x() const { return 0.5 * (front_x() + fork_tip_x()); }
};

/// Actuator limits. The drive and the steering answer a held command with a first-order lag, bounded by an
/// acceleration and a steering-rate limit. The thesis gives none of these; the values are those of a typical
/// electric pallet stacker (10 km/h top speed [Stacker thesis, section 4.2.3]).
struct TricycleParams {
  TricycleGeometry geometry;
  double max_wheel_speed = 2.5;                 ///< |v_steer|, m/s (10 km/h is 2.78 m/s)
  double max_steer_angle = 1.5707963267948966;  ///< |theta_steer|, rad: +-pi/2 [Stacker thesis, section 5.2]
  double max_steer_rate = 1.2;                  ///< rad/s
  double max_wheel_acceleration = 0.8;          ///< m/s^2
  double drive_time_constant = 0.15;            ///< s
  double steer_time_constant = 0.08;            ///< s
  /// Longest internal integration step; step() subdivides longer calls.
  double max_substep = 0.005;  ///< s
};

/// What the drive-steering wheel is asked to do [Stacker thesis, eq. 5.9].
struct TricycleCommand {
  double v_steer = 0.0;      ///< wheel ground speed, m/s (negative drives the stacker backwards when theta = 0)
  double theta_steer = 0.0;  ///< steering angle, rad, counter-clockwise from the body x axis

  friend bool operator==(const TricycleCommand&, const TricycleCommand&) = default;
};

struct TricycleState {
  geometry::Pose2 pose;      ///< rear-axle midpoint in the map frame
  double v_steer = 0.0;      ///< actual wheel ground speed, m/s
  double theta_steer = 0.0;  ///< actual steering angle, rad
};

/// Motion of the rear-axle midpoint: signed speed along the body x axis and yaw rate.
struct TricycleRates {
  double v = 0.0;         ///< m/s
  double yaw_rate = 0.0;  ///< rad/s
};

/// Forward kinematics [Stacker thesis, eq. 5.7/5.8]: v = v_steer cos(theta), phi' = v_steer/L sin(theta).
TricycleRates forward_kinematics(const TricycleCommand& wheel, double wheelbase);

/// Inverse kinematics [Stacker thesis, eq. 5.12, 5.16, 5.17] for a signed speed v of the rear-axle midpoint:
/// theta_steer = atan(phi' L / v), v_steer = sign(v) sqrt(v^2 + phi'^2 L^2). The thesis writes the unsigned form;
/// keeping the sign of v in the atan is what makes reversing turn the right way. v = 0 with phi' != 0 is the pivot
/// about the rear axle, theta = +-pi/2, taken as the limit v -> 0+ (theta = sign(phi') pi/2, v_steer = |phi'| L).
TricycleCommand inverse_kinematics(const TricycleRates& rates, double wheelbase);

/// The outline relative to the rear-axle midpoint, counter-clockwise: the chassis with both forks (a U shape).
geometry::Polygon tricycle_footprint(const TricycleGeometry& geometry);
/// The chassis alone (convex), relative to the rear-axle midpoint.
geometry::Polygon tricycle_chassis(const TricycleGeometry& geometry);
/// Left and right fork (convex each), relative to the rear-axle midpoint.
std::array<geometry::Polygon, 2> tricycle_forks(const TricycleGeometry& geometry);
/// Any body-frame polygon placed at `pose`.
geometry::Polygon polygon_in_map(const geometry::Pose2& pose, const geometry::Polygon& body_polygon);
/// Midpoint between the two fork tips in the map frame.
geometry::Vec2 fork_tip_midpoint(const geometry::Pose2& pose, const TricycleGeometry& geometry);

/// The simulated truth of one stacker. Commands are held between calls; each step applies steering-angle and
/// wheel-speed limits, the first-order actuator lag, then integrates the pose exactly along the arc of every
/// sub-step (the mean wheel state over the sub-step moves the body).
///
/// Not thread-safe: one owner steps it.
class Tricycle {
 public:
  /// Throws std::invalid_argument on non-positive or non-finite limits.
  Tricycle(const TricycleParams& params, const geometry::Pose2& start);

  /// Holds `command` from now on. Non-finite values are treated as a stop with the steering kept.
  void command(const TricycleCommand& command);
  /// Advances `dt` seconds under the held command; dt <= 0 or non-finite does nothing.
  void step(double dt);
  /// command() then step().
  void step(const TricycleCommand& command, double dt);
  /// Puts the stacker at `pose`, at rest with the wheel straight.
  void reset(const geometry::Pose2& pose);
  /// Moves the stacker to `pose`, its wheel's speed, angle and held command kept: a prediction
  /// started from a pose estimate.
  void move_to(const geometry::Pose2& pose) { state_.pose = pose; }

  const TricycleState& state() const { return state_; }
  const geometry::Pose2& pose() const { return state_.pose; }
  /// The held command after saturation.
  const TricycleCommand& held_command() const { return command_; }
  /// Current motion of the rear-axle midpoint.
  TricycleRates rates() const;
  /// Map-frame outline (chassis and forks) at the true pose.
  geometry::Polygon footprint_in_map() const;
  const TricycleParams& params() const { return params_; }

 private:
  void substep(double h);

  TricycleParams params_;
  TricycleState state_;
  TricycleCommand command_;
};

}  // namespace fleet::sim
