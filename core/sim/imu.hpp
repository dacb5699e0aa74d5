#pragma once

#include <random>

namespace fleet::sim {

/// A MEMS yaw-rate gyro (70 Hz [Forklift thesis, Table 3.1]). Defaults are those of a consumer 9-axis
/// IMU after start-up bias calibration.
struct GyroParams {
  double rate_hz = 70.0;
  double noise_std = 0.005;          ///< white noise per sample, rad/s
  double bias_initial_std = 0.002;   ///< residual bias at start, rad/s
  double bias_random_walk = 2.0e-4;  ///< bias drift, rad/s per sqrt(s)
};

class Gyro {
 public:
  /// Draws the initial bias from `rng`; all later noise comes from the same engine.
  Gyro(const GyroParams& params, std::mt19937_64 rng);

  /// One reading of the true yaw rate `omega`, `dt` seconds after the previous one (the bias
  /// wanders by a random walk over dt).
  double measure(double omega, double dt);

  double bias() const { return bias_; }
  const GyroParams& params() const { return params_; }

 private:
  GyroParams params_;
  std::mt19937_64 rng_;
  double bias_ = 0.0;
};

}  // namespace fleet::sim
