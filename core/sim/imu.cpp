#include "sim/imu.hpp"

#include <cmath>

namespace fleet::sim {

Gyro::Gyro(const GyroParams& params, std::mt19937_64 rng) : params_(params), rng_(rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  bias_ = params_.bias_initial_std * n(rng_);
}

double Gyro::measure(double omega, double dt) {
  std::normal_distribution<double> n(0.0, 1.0);
  if (dt > 0.0 && std::isfinite(dt)) bias_ += params_.bias_random_walk * std::sqrt(dt) * n(rng_);
  return omega + bias_ + params_.noise_std * n(rng_);
}

}  // namespace fleet::sim
