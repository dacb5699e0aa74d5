#pragma once

#include <random>

#include "sim/mecanum.hpp"

namespace fleet::sim {

/// Wheel encoders. The seed's forklifts had none (its conclusion regrets it), so they are off by
/// default; the simulation can switch them on to measure what they would bring.
struct EncoderParams {
  bool enabled = false;
  double rate_hz = 70.0;
  double ticks_per_rev = 360.0;  ///< quantisation of the wheel angle
  double noise_std = 0.02;       ///< extra speed noise per reading, rad/s
};

class WheelEncoders {
 public:
  WheelEncoders(const EncoderParams& params, std::mt19937_64 rng);

  /// Wheel speeds measured over the last `dt` seconds from the true wheel speeds: the angle
  /// travelled is quantised to ticks (the remainder carries over), then noise is added.
  WheelSpeeds measure(const WheelSpeeds& true_speeds, double dt);

  const EncoderParams& params() const { return params_; }

 private:
  EncoderParams params_;
  std::mt19937_64 rng_;
  WheelSpeeds residual_angle_{};
};

}  // namespace fleet::sim
