#pragma once

#include <cstddef>
#include <vector>

#include "control/twist.hpp"
#include "geometry/pose.hpp"

namespace fleet::control {

/// Settings of the picker's waypoint controller [Picker thesis, section 4.3.2.1]. The seed gives the laws but none of
/// the values except U_M (0.3 m/s in the tests, 1 m/s in Fig. 4.29); the rest are chosen here.
struct WaypointControllerParams {
  double period = 0.02;              ///< T, the sampling period of eq. 4.14-4.16 (the encoder rate, 50 Hz), s
  double tau_u = 0.1;                ///< τ_u, smooths the forward speed [Picker thesis, eq. 4.15], s
  double tau_r = 0.1;                ///< τ_r, smooths the yaw rate [Picker thesis, eq. 4.16], s
  double max_speed = 0.3;            ///< U_M of f_sat [Picker thesis, eq. 4.15, Fig. 4.28], m/s
  double decel_distance = 0.5;       ///< D_XM: f_sat ramps down linearly within this distance
                                     ///< [Picker thesis, Fig. 4.28], m
  double k_y = 1.5;                  ///< K_Y [Picker thesis, eq. 4.16]; K_Y·d·sin α is a yaw rate, so K_Y is in
                                     ///< rad/(m·s)
  double max_omega = 0.6;            ///< the cap on K_Y·d [Picker thesis, text after eq. 4.16], rad/s
  double look_ahead = 0.0;           ///< L: point P, L ahead of the centre M, is driven onto the waypoint
                                     ///< [Picker thesis, eq. 4.11]
  double waypoint_tolerance = 0.15;  ///< an intermediate waypoint is passed once Ge [Picker thesis, eq. 4.17] is below
                                     ///< this, m
  double goal_tolerance = 0.03;      ///< the last waypoint is reached once Ge is below this; then the base stops, m
};

/// The geometry of one waypoint seen from the robot [Picker thesis, eq. 4.10-4.12].
struct WaypointErrors {
  double x_wr = 0.0;   ///< X_WR: the waypoint in the robot frame [Picker thesis, eq. 4.10], m
  double y_wr = 0.0;   ///< Y_WR, m
  double d = 0.0;      ///< distance from the centre M to the waypoint, m
  double alpha = 0.0;  ///< bearing of the waypoint, atan2(Y_WR, X_WR) (the seed's atan(Y/X) folds a waypoint behind
                       ///< the robot onto one ahead), rad
  double e_x = 0.0;    ///< e_XR = d·cos α − L [Picker thesis, eq. 4.12], m
  double e_y = 0.0;    ///< e_YR = d·sin α [Picker thesis, eq. 4.12], m
  double ge = 0.0;     ///< Ge = √(e_X² + e_Y²) [Picker thesis, eq. 4.17], m
};

/// Eq. 4.10-4.12 and 4.17 for the robot at `robot` and the waypoint `waypoint` (map frame).
WaypointErrors waypoint_errors(const geometry::Pose2& robot, geometry::Vec2 waypoint, double look_ahead);

/// f_sat(e_X, U_M, D_XM) of [Picker thesis, eq. 4.15, Fig. 4.28]: U_M·e_X/D_XM, clipped to ±U_M (symmetric, so that
/// an overshot waypoint is backed onto).
double speed_saturation(double e_x, double max_speed, double decel_distance);

/// The scale factor of eq. 4.15, printed |1 − sin α|. That is 2 for a waypoint on the right (α = −π/2) and 0 on the
/// left, whereas the text says it is largest at α = 0 and reduced by the turn: 1 − |sin α| is used.
double turn_speed_scale(double alpha);

/// Drives the picker's base through a sequence of waypoints [Picker thesis, section 4.3.2]: forward speed by
/// eq. 4.15, yaw rate by eq. 4.16 (K_Y·d capped at max_omega), both through first-order filters of time constants
/// τ_u, τ_r discretised with the period T (Euler, Picker thesis, eq. 4.14). The sideways speed stays 0, as in the seed,
/// although the base is holonomic. Call update() once every `period`.
class WaypointController {
 public:
  explicit WaypointController(const WaypointControllerParams& params = {});

  /// Starts a new sequence (the filters keep their state, so a moving base is not jerked). Empty: stop.
  void set_waypoints(std::vector<geometry::Vec2> waypoints);

  /// One control step from the estimated pose (map frame): the body twist to command.
  BodyTwist update(const geometry::Pose2& pose);

  /// Sets the filter states u_{n−1}, ω_{n−1} to 0 (the base at rest).
  void reset_filters();

  bool done() const { return index_ >= waypoints_.size(); }
  std::size_t current_index() const { return index_; }
  /// Eq. 4.10-4.12 of the last update(), towards the waypoint then current.
  const WaypointErrors& errors() const { return errors_; }
  const WaypointControllerParams& params() const { return params_; }

 private:
  WaypointControllerParams params_;
  std::vector<geometry::Vec2> waypoints_;
  std::size_t index_ = 0;
  WaypointErrors errors_;
  double u_ = 0.0;      ///< u_{n−1}, m/s
  double omega_ = 0.0;  ///< ω_{n−1}, rad/s
};

}  // namespace fleet::control
