#include "control/waypoint_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace fleet::control {

WaypointErrors waypoint_errors(const geometry::Pose2& robot, geometry::Vec2 waypoint, double look_ahead) {
  WaypointErrors e;
  // [Picker thesis, eq. 4.10]: the waypoint in the robot frame.
  const double c = std::cos(robot.yaw);
  const double s = std::sin(robot.yaw);
  const double dx = waypoint.x - robot.x;
  const double dy = waypoint.y - robot.y;
  e.x_wr = c * dx + s * dy;
  e.y_wr = -s * dx + c * dy;
  e.d = std::hypot(e.x_wr, e.y_wr);
  e.alpha = e.d > 0.0 ? std::atan2(e.y_wr, e.x_wr) : 0.0;
  // [Picker thesis, eq. 4.12]; d·cos α = X_WR and d·sin α = Y_WR.
  e.e_x = e.d * std::cos(e.alpha) - look_ahead;
  e.e_y = e.d * std::sin(e.alpha);
  e.ge = std::hypot(e.e_x, e.e_y);  // [Picker thesis, eq. 4.17]
  return e;
}

double speed_saturation(double e_x, double max_speed, double decel_distance) {
  // [Picker thesis, Fig. 4.28]: linear within D_XM of the waypoint, U_M beyond.
  return std::clamp(max_speed * e_x / decel_distance, -max_speed, max_speed);
}

double turn_speed_scale(double alpha) {
  return 1.0 - std::abs(std::sin(alpha));  // [Picker thesis, eq. 4.15], printed |1 − sin α|
}

WaypointController::WaypointController(const WaypointControllerParams& p) : params_(p) {
  if (!(p.period > 0.0) || !(p.tau_u >= 0.0) || !(p.tau_r >= 0.0) || !(p.max_speed > 0.0) ||
      !(p.decel_distance > 0.0) || !(p.k_y >= 0.0) || !(p.max_omega >= 0.0) || !(p.look_ahead >= 0.0) ||
      !(p.waypoint_tolerance > 0.0) || !(p.goal_tolerance > 0.0)) {
    throw std::invalid_argument(
        "WaypointControllerParams: period, max_speed, decel_distance and the tolerances must be positive, the time "
        "constants, gains and look_ahead non-negative");
  }
}

void WaypointController::set_waypoints(std::vector<geometry::Vec2> waypoints) {
  waypoints_ = std::move(waypoints);
  index_ = 0;
}

void WaypointController::reset_filters() {
  u_ = 0.0;
  omega_ = 0.0;
}

BodyTwist WaypointController::update(const geometry::Pose2& pose) {
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw)) {
    reset_filters();
    return {};
  }
  // Pass every waypoint already within its tolerance; the last one ends the run.
  while (index_ < waypoints_.size()) {
    errors_ = waypoint_errors(pose, waypoints_[index_], params_.look_ahead);
    const bool last = index_ + 1 == waypoints_.size();
    if (errors_.ge >= (last ? params_.goal_tolerance : params_.waypoint_tolerance)) break;
    ++index_;
  }
  if (done()) {
    reset_filters();
    return {};
  }
  const double T = params_.period;
  // [Picker thesis, eq. 4.15] with the scale 1 − |sin α| (see turn_speed_scale).
  const double target_u =
      speed_saturation(errors_.e_x, params_.max_speed, params_.decel_distance) * turn_speed_scale(errors_.alpha);
  u_ = params_.tau_u / (T + params_.tau_u) * u_ + T / (T + params_.tau_u) * target_u;
  // [Picker thesis, eq. 4.16], K_Y·d capped at the largest allowed yaw rate (Picker thesis, text after eq. 4.16).
  const double gain = std::min(params_.k_y * errors_.d, params_.max_omega);
  const double target_omega = gain * std::sin(errors_.alpha);
  omega_ = params_.tau_r / (T + params_.tau_r) * omega_ + T / (T + params_.tau_r) * target_omega;
  return {u_, 0.0, omega_};
}

}  // namespace fleet::control
