#include "sim/tricycle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fleet::sim {

namespace {

bool positive(double x) {
  return std::isfinite(x) && x > 0.0;
}
bool non_negative(double x) {
  return std::isfinite(x) && x >= 0.0;
}

/// One actuator over a sub-step h: the first-order lag towards a held `target`, exact, bounded by `max_change`.
struct ActuatorStep {
  double end = 0.0;   ///< value at the end of the sub-step
  double mean = 0.0;  ///< mean value over the sub-step (what moves the body)
};

ActuatorStep lag_towards(double value, double target, double time_constant, double max_change, double h) {
  const double decay = time_constant > 0.0 ? std::exp(-h / time_constant) : 0.0;
  const double lagged = target + (value - target) * decay;
  if (std::abs(lagged - value) <= max_change) {
    // Mean of target + (value - target) e^(-t/tau) over [0, h].
    const double start_share = time_constant > 0.0 ? time_constant / h * (1.0 - decay) : 0.0;
    return {lagged, target + (value - target) * start_share};
  }
  // Rate-limited: a linear ramp.
  const double end = value + std::copysign(max_change, lagged - value);
  return {end, 0.5 * (value + end)};
}

}  // namespace

TricycleRates forward_kinematics(const TricycleCommand& wheel, double wheelbase) {
  return {wheel.v_steer * std::cos(wheel.theta_steer), wheel.v_steer / wheelbase * std::sin(wheel.theta_steer)};
}

TricycleCommand inverse_kinematics(const TricycleRates& rates, double wheelbase) {
  const double turn = rates.yaw_rate * wheelbase;  // lateral speed of the drive wheel
  if (rates.v == 0.0) {
    if (turn == 0.0) return {0.0, 0.0};
    return {std::abs(turn), std::copysign(std::numbers::pi / 2.0, turn)};
  }
  const double speed = std::hypot(rates.v, turn);
  return {std::copysign(speed, rates.v), std::atan(turn / rates.v)};
}

geometry::Polygon tricycle_chassis(const TricycleGeometry& g) {
  const double w = g.width / 2.0;
  return {{g.chassis_back_x(), -w}, {g.front_x(), -w}, {g.front_x(), w}, {g.chassis_back_x(), w}};
}

std::array<geometry::Polygon, 2> tricycle_forks(const TricycleGeometry& g) {
  std::array<geometry::Polygon, 2> forks;
  for (int side = 0; side < 2; ++side) {
    const double c = (side == 0 ? 0.5 : -0.5) * g.fork_spacing;
    const double lo = c - g.fork_width / 2.0;
    const double hi = c + g.fork_width / 2.0;
    forks[static_cast<std::size_t>(side)] = {
        {g.fork_tip_x(), lo}, {g.chassis_back_x(), lo}, {g.chassis_back_x(), hi}, {g.fork_tip_x(), hi}};
  }
  return forks;
}

geometry::Polygon tricycle_footprint(const TricycleGeometry& g) {
  const double w = g.width / 2.0;
  const double back = g.chassis_back_x();
  const double tip = g.fork_tip_x();
  const double outer = (g.fork_spacing + g.fork_width) / 2.0;
  const double inner = (g.fork_spacing - g.fork_width) / 2.0;
  // Counter-clockwise from the front right corner, round the chassis, then down the left fork, up the gap and
  // down the right fork.
  return {{g.front_x(), -w}, {g.front_x(), w}, {back, w},     {back, outer}, {tip, outer},   {tip, inner},
          {back, inner},     {back, -inner},   {tip, -inner}, {tip, -outer}, {back, -outer}, {back, -w}};
}

geometry::Polygon polygon_in_map(const geometry::Pose2& pose, const geometry::Polygon& body_polygon) {
  geometry::Polygon out;
  out.reserve(body_polygon.size());
  for (const geometry::Vec2& p : body_polygon) out.push_back(geometry::body_to_map(pose, p));
  return out;
}

geometry::Vec2 fork_tip_midpoint(const geometry::Pose2& pose, const TricycleGeometry& g) {
  return geometry::body_to_map(pose, {g.fork_tip_x(), 0.0});
}

Tricycle::Tricycle(const TricycleParams& params, const geometry::Pose2& start) : params_(params) {
  const TricycleGeometry& g = params_.geometry;
  if (!positive(g.wheelbase) || !positive(g.length) || !positive(g.width) || !positive(params_.max_wheel_speed) ||
      !positive(params_.max_steer_angle) || params_.max_steer_angle > std::numbers::pi / 2.0 + 1e-12 ||
      !positive(params_.max_steer_rate) || !positive(params_.max_wheel_acceleration) ||
      !non_negative(params_.drive_time_constant) || !non_negative(params_.steer_time_constant) ||
      !positive(params_.max_substep)) {
    throw std::invalid_argument(
        "TricycleParams: wheelbase, length, width, max_wheel_speed, max_steer_rate, max_wheel_acceleration and "
        "max_substep must be > 0, max_steer_angle in (0, pi/2], time constants >= 0");
  }
  reset(start);
}

void Tricycle::reset(const geometry::Pose2& pose) {
  state_ = {};
  state_.pose = pose;
  command_ = {};
}

void Tricycle::command(const TricycleCommand& command) {
  if (!std::isfinite(command.v_steer) || !std::isfinite(command.theta_steer)) {
    command_ = {0.0, state_.theta_steer};
    return;
  }
  command_.v_steer = std::clamp(command.v_steer, -params_.max_wheel_speed, params_.max_wheel_speed);
  command_.theta_steer = std::clamp(command.theta_steer, -params_.max_steer_angle, params_.max_steer_angle);
}

void Tricycle::step(const TricycleCommand& command, double dt) {
  this->command(command);
  step(dt);
}

void Tricycle::step(double dt) {
  if (!std::isfinite(dt) || dt <= 0.0) return;
  const int n = static_cast<int>(std::ceil(dt / params_.max_substep));
  const double h = dt / n;
  for (int i = 0; i < n; ++i) substep(h);
}

TricycleRates Tricycle::rates() const {
  return forward_kinematics({state_.v_steer, state_.theta_steer}, params_.geometry.wheelbase);
}

geometry::Polygon Tricycle::footprint_in_map() const {
  return polygon_in_map(state_.pose, tricycle_footprint(params_.geometry));
}

void Tricycle::substep(double h) {
  const TricycleState before = state_;
  const ActuatorStep steer =
      lag_towards(before.theta_steer, command_.theta_steer, params_.steer_time_constant, params_.max_steer_rate * h, h);
  const ActuatorStep drive =
      lag_towards(before.v_steer, command_.v_steer, params_.drive_time_constant, params_.max_wheel_acceleration * h, h);
  state_.theta_steer = steer.end;
  state_.v_steer = drive.end;
  // The mean wheel state over the sub-step moves the body; with it the motion over h is a circular arc of the
  // rear-axle midpoint [Stacker thesis, eq. 5.7], integrated exactly.
  const TricycleRates r = forward_kinematics({drive.mean, steer.mean}, params_.geometry.wheelbase);
  const double dth = r.yaw_rate * h;
  double forward = r.v * h;
  double sideways = 0.0;
  if (std::abs(dth) > 1e-12) {
    forward = r.v * std::sin(dth) / r.yaw_rate;
    sideways = r.v * (1.0 - std::cos(dth)) / r.yaw_rate;
  }
  const geometry::Vec2 p = geometry::body_to_map(before.pose, {forward, sideways});
  state_.pose = {p.x, p.y, geometry::normalize_angle(before.pose.yaw + dth)};
}

}  // namespace fleet::sim
