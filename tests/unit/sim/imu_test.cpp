#include "sim/imu.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/encoders.hpp"

using namespace fleet::sim;

TEST(Gyro, NoiseAndBiasHaveTheConfiguredSize) {
  GyroParams p;
  p.bias_random_walk = 0.0;
  p.bias_initial_std = 0.01;
  Gyro gyro(p, std::mt19937_64(3));
  const int n = 20000;
  double sum = 0.0;
  double sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const double z = gyro.measure(0.5, 1.0 / 70.0) - 0.5;
    sum += z;
    sq += z * z;
  }
  const double mean = sum / n;
  EXPECT_NEAR(mean, gyro.bias(), 4.0 * p.noise_std / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sq / n - mean * mean), p.noise_std, 0.05 * p.noise_std);
}

TEST(Gyro, BiasWandersAsARandomWalk) {
  GyroParams p;
  p.noise_std = 0.0;
  p.bias_initial_std = 0.0;
  p.bias_random_walk = 1e-3;
  // Over 100 s the bias std is 1e-3 * 10 = 0.01 rad/s; check across seeds.
  double sq = 0.0;
  const int runs = 200;
  for (int s = 0; s < runs; ++s) {
    Gyro gyro(p, std::mt19937_64(s));
    for (int i = 0; i < 1000; ++i) gyro.measure(0.0, 0.1);
    sq += gyro.bias() * gyro.bias();
  }
  EXPECT_NEAR(std::sqrt(sq / runs), 0.01, 0.0015);
}

TEST(WheelEncoders, QuantisedSpeedsAverageToTheTruth) {
  EncoderParams p;
  p.enabled = true;
  p.noise_std = 0.0;
  WheelEncoders enc(p, std::mt19937_64(1));
  const WheelSpeeds truth{3.3, -2.1, 0.7, 6.0};
  WheelSpeeds sum{};
  const int n = 700;
  for (int i = 0; i < n; ++i) {
    const WheelSpeeds w = enc.measure(truth, 1.0 / 70.0);
    for (int k = 0; k < 4; ++k) sum[k] += w[k];
  }
  // The carried-over remainder bounds the error of the mean by one tick over the whole window.
  const double tick = 2.0 * 3.141592653589793 / p.ticks_per_rev;
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(sum[k] / n, truth[k], tick / (n / 70.0) + 1e-12);
}
