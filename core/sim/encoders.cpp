#include "sim/encoders.hpp"

#include <cmath>
#include <numbers>

namespace fleet::sim {

WheelEncoders::WheelEncoders(const EncoderParams& params, std::mt19937_64 rng) : params_(params), rng_(rng) {}

WheelSpeeds WheelEncoders::measure(const WheelSpeeds& true_speeds, double dt) {
  WheelSpeeds out{};
  if (!(dt > 0.0) || !std::isfinite(dt)) return out;
  const double tick = 2.0 * std::numbers::pi / params_.ticks_per_rev;
  std::normal_distribution<double> n(0.0, params_.noise_std);
  for (int i = 0; i < 4; ++i) {
    // Count whole ticks; the fraction of a tick stays in residual_angle_ for the next reading.
    const double angle = residual_angle_[i] + true_speeds[i] * dt;
    const double counted = std::trunc(angle / tick) * tick;
    residual_angle_[i] = angle - counted;
    out[i] = counted / dt + (params_.noise_std > 0.0 ? n(rng_) : 0.0);
  }
  return out;
}

}  // namespace fleet::sim
