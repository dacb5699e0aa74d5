#include "sim/summit_xls.hpp"

#include <cmath>

namespace fleet::sim {

ForkliftParams summit_xls_body_params() {
  ForkliftParams p;
  p.mecanum.wheel_radius = 0.127;
  p.mecanum.half_wheelbase = 0.195;
  p.mecanum.half_track = 0.20;
  p.mecanum.max_wheel_speed = SummitXlsSpeeds::kTop / p.mecanum.wheel_radius;  // 3 m/s [Picker thesis, section 3.1.1]
  p.footprint = {0.65, 0.50};
  p.wheel_time_constant = 0.075;  // Fig. 4.27's ~0.3 s step response, see the header
  return p;
}

EncoderParams summit_xls_encoder_params() {
  EncoderParams e;
  e.enabled = true;
  e.rate_hz = 50.0;
  e.ticks_per_rev = 4096.0;
  e.noise_std = 0.01;
  return e;
}

WheelOdometry::WheelOdometry(const MecanumParams& params, const geometry::Pose2& start)
    : kinematics_(params), pose_(start) {}

BodyTwist WheelOdometry::update(const WheelSpeeds& wheels, double dt) {
  for (double w : wheels) {
    if (!std::isfinite(w)) return {};
  }
  const BodyTwist t = kinematics_.forward(wheels);  // [Picker thesis, eq. 3.7]
  if (!std::isfinite(dt) || dt <= 0.0) return t;
  const double dth = t.omega * dt;
  double bx = t.vx * dt;
  double by = t.vy * dt;
  if (std::abs(dth) > 1e-9) {
    const double s = std::sin(dth) / dth;
    const double c = (1.0 - std::cos(dth)) / dth;
    bx = s * t.vx * dt - c * t.vy * dt;
    by = c * t.vx * dt + s * t.vy * dt;
  }
  const double cy = std::cos(pose_.yaw);
  const double sy = std::sin(pose_.yaw);
  pose_.x += cy * bx - sy * by;
  pose_.y += sy * bx + cy * by;
  pose_.yaw = geometry::normalize_angle(pose_.yaw + dth);
  return t;
}

}  // namespace fleet::sim
