#include "sim/mecanum.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fleet::sim {

MecanumKinematics::MecanumKinematics(const MecanumParams& params) : params_(params) {
  if (!(params_.wheel_radius > 0.0) || !(params_.half_wheelbase > 0.0) || !(params_.half_track > 0.0) ||
      !(params_.max_wheel_speed > 0.0)) {
    throw std::invalid_argument(
        "MecanumParams: wheel_radius, half_wheelbase, half_track and "
        "max_wheel_speed must be positive (wheel_radius=" +
        std::to_string(params_.wheel_radius) + ")");
  }
}

WheelSpeeds MecanumKinematics::inverse(const BodyTwist& t) const {
  // [Forklift thesis, eq. 6.1]
  const double l = params_.half_wheelbase + params_.half_track;
  const double k = 1.0 / params_.wheel_radius;
  return {k * (t.vx - t.vy - l * t.omega), k * (t.vx + t.vy + l * t.omega), k * (t.vx + t.vy - l * t.omega),
          k * (t.vx - t.vy + l * t.omega)};
}

BodyTwist MecanumKinematics::forward(const WheelSpeeds& w) const {
  // [Picker thesis, eq. 3.7] (r/4 matrix), rows reordered to the wheel numbering of [Forklift thesis, eq. 6.1] so that
  // forward(inverse(t)) == t.
  const double l = params_.half_wheelbase + params_.half_track;
  const double k = params_.wheel_radius / 4.0;
  return {k * (w[0] + w[1] + w[2] + w[3]), k * (-w[0] + w[1] + w[2] - w[3]), k / l * (-w[0] + w[1] - w[2] + w[3])};
}

WheelSpeeds MecanumKinematics::saturate(const WheelSpeeds& w) const {
  double peak = 0.0;
  for (double s : w) peak = std::max(peak, std::abs(s));
  if (peak <= params_.max_wheel_speed) return w;
  const double scale = params_.max_wheel_speed / peak;
  return {w[0] * scale, w[1] * scale, w[2] * scale, w[3] * scale};
}

BodyTwist MecanumKinematics::limit(const BodyTwist& twist) const {
  return forward(saturate(inverse(twist)));
}

BodyLimits MecanumKinematics::limits() const {
  const double l = params_.half_wheelbase + params_.half_track;
  return {params_.wheel_radius * params_.max_wheel_speed, params_.wheel_radius * params_.max_wheel_speed / l};
}

}  // namespace fleet::sim
