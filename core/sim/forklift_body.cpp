#include "sim/forklift_body.hpp"

#include <cmath>
#include <stdexcept>

namespace fleet::sim {

ForkliftBody::ForkliftBody(const ForkliftParams& params, const geometry::Pose2& start, std::mt19937_64 rng)
    : params_(params), kinematics_(params.mecanum), rng_(rng), pose_(start) {
  if (!(params_.wheel_time_constant >= 0.0) || !(params_.slip_std >= 0.0) || !(params_.slip_correlation_time > 0.0) ||
      !(params_.max_substep > 0.0)) {
    throw std::invalid_argument(
        "ForkliftParams: wheel_time_constant, slip_std must be >= 0 and "
        "slip_correlation_time, max_substep > 0");
  }
  if (params_.slip_std > 0.0) {
    std::normal_distribution<double> n(0.0, params_.slip_std);
    for (double& s : slip_) s = n(rng_);
  }
}

void ForkliftBody::reset(const geometry::Pose2& pose) {
  pose_ = pose;
  twist_ = {};
  command_ = {};
  wheels_ = {};
}

geometry::Polygon ForkliftBody::footprint_polygon(double margin) const {
  return geometry::footprint_polygon(pose_, params_.footprint, margin);
}

void ForkliftBody::step(const BodyTwist& cmd, double dt) {
  if (!std::isfinite(dt) || dt <= 0.0) return;
  BodyTwist safe = cmd;
  if (!std::isfinite(cmd.vx) || !std::isfinite(cmd.vy) || !std::isfinite(cmd.omega)) safe = {};
  const WheelSpeeds target = kinematics_.saturate(kinematics_.inverse(safe));
  command_ = kinematics_.forward(target);
  const int n = static_cast<int>(std::ceil(dt / params_.max_substep));
  const double h = dt / n;
  for (int i = 0; i < n; ++i) substep(target, h);
}

void ForkliftBody::substep(const WheelSpeeds& target, double dt) {
  // First-order servo response, [Picker thesis, eq. 4.29], discretised exactly for a held command.
  // The mean wheel speed over the step (not its end value) moves the body, so that the distance
  // travelled is exact for the lag too.
  const double tau = params_.wheel_time_constant;
  const double alpha = tau > 0.0 ? 1.0 - std::exp(-dt / tau) : 1.0;
  const double mean_weight = tau > 0.0 ? tau / dt * alpha : 0.0;  // share of the start value in the mean
  WheelSpeeds ground{};                                           // mean ground speed over the step, moves the body
  WheelSpeeds ground_end{};                                       // at the end of the step, reported by twist()
  const double phi = std::exp(-dt / params_.slip_correlation_time);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 4; ++i) {
    const double mean = target[i] + mean_weight * (wheels_[i] - target[i]);
    wheels_[i] += alpha * (target[i] - wheels_[i]);
    if (params_.slip_std > 0.0) {
      // Gauss-Markov slip: stationary std slip_std, correlation time slip_correlation_time.
      slip_[i] = phi * slip_[i] + params_.slip_std * std::sqrt(1.0 - phi * phi) * n(rng_);
    }
    ground[i] = mean * (1.0 + slip_[i]);
    ground_end[i] = wheels_[i] * (1.0 + slip_[i]);
  }
  twist_ = kinematics_.forward(ground_end);
  const BodyTwist motion = kinematics_.forward(ground);

  // Exact integration of a constant body twist over dt (a circular arc).
  const double th = pose_.yaw;
  const double dth = motion.omega * dt;
  double dx_body = motion.vx * dt;
  double dy_body = motion.vy * dt;
  if (std::abs(dth) > 1e-9) {
    const double s = std::sin(dth) / dth;
    const double c = (1.0 - std::cos(dth)) / dth;
    const double bx = motion.vx * dt;
    const double by = motion.vy * dt;
    dx_body = s * bx - c * by;
    dy_body = c * bx + s * by;
  }
  pose_.x += std::cos(th) * dx_body - std::sin(th) * dy_body;
  pose_.y += std::sin(th) * dx_body + std::cos(th) * dy_body;
  pose_.yaw = geometry::normalize_angle(th + dth);
}

}  // namespace fleet::sim
