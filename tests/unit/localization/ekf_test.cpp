#include "localization/ekf.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "geometry/pose.hpp"
#include "sim/imu.hpp"

using namespace fleet::localization;
using fleet::geometry::Pose2;
using fleet::geometry::Vec2;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
using ::fleet::geometry::kDeg;

StateVector some_state(double theta) {
  StateVector x;
  x << 1.2, 0.7, theta, 0.18, -0.04, 0.3, 0.004;  // the last one: gyro bias, rad/s
  return x;
}

// Drives a point along a circle of radius 0.5 m at 0.2 m/s and feeds a filter 70 Hz gyro
// readings, commanded velocities and 20 Hz noisy antenna fixes.
struct CircleRun {
  double heading_error = 0.0;
  double position_error = 0.0;
  Ekf ekf;
  explicit CircleRun(const EkfParams& p) : ekf(p) {}
};

// A forklift on a circle (radius 1 m at 0.2 m/s) that stops for `stop_s` seconds after every
// `drive_s` seconds of driving (stop_s = 0: never), with a real gyro (white noise and a
// random-walk bias, sim::Gyro), 20 Hz fixes with 4 cm noise and the drive command fed to the
// filter as an agent does. Records the bias estimation error at the end of every stop, and the
// heading error over the whole run.
struct StopAndGo {
  std::vector<double> bias_error_at_stop_end;  ///< rad/s
  double final_bias_error = 0.0;               ///< rad/s
  double true_bias_final = 0.0;                ///< rad/s
  double heading_rmse = 0.0;                   ///< rad
};

StopAndGo run_stop_and_go(const EkfParams& params, const fleet::sim::GyroParams& gyro_params, double drive_s,
                          double stop_s, double seconds, std::uint64_t seed, double extra_bias = 0.0) {
  StopAndGo out;
  Ekf ekf(params);
  fleet::sim::Gyro gyro(gyro_params, std::mt19937_64(seed));
  std::mt19937_64 rng(seed + 100);
  std::normal_distribution<double> fix_noise(0.0, 0.04);
  const double dt = 1.0 / 70.0;
  Pose2 truth{1.5, 1.0, 0.0};
  double sq = 0.0;
  long n = 0;
  bool was_stopped = false;
  for (int k = 0; k <= static_cast<int>(seconds * 70.0); ++k) {
    const double t = k * dt;
    const bool stopped = stop_s > 0.0 && std::fmod(t, drive_s + stop_s) >= drive_s;
    const double v = stopped ? 0.0 : 0.2;
    const double omega = stopped ? 0.0 : 0.2;
    if (k > 0) {
      truth.x += v * dt * std::cos(truth.yaw + 0.5 * omega * dt);
      truth.y += v * dt * std::sin(truth.yaw + 0.5 * omega * dt);
      truth.yaw += omega * dt;
      ekf.predict(gyro.measure(omega, dt) + extra_bias, dt);
      ekf.update_commanded({v, 0.0, omega});
    }
    if ((k * 20) % 70 < 20) {
      const Vec2 antenna = fleet::geometry::body_to_map(truth, params.antenna_offset);
      ekf.update_uwb({antenna.x + fix_noise(rng), antenna.y + fix_noise(rng)},
                     0.04 * 0.04 * Eigen::Matrix2d::Identity());
    }
    if (was_stopped && !stopped) out.bias_error_at_stop_end.push_back(ekf.gyro_bias() - gyro.bias() - extra_bias);
    was_stopped = stopped;
    if (ekf.initialized() && t > 5.0) {
      const double e = fleet::geometry::angle_diff(ekf.pose().yaw, truth.yaw);
      sq += e * e;
      ++n;
    }
  }
  out.final_bias_error = ekf.gyro_bias() - gyro.bias() - extra_bias;
  out.true_bias_final = gyro.bias() + extra_bias;
  out.heading_rmse = n > 0 ? std::sqrt(sq / static_cast<double>(n)) : 0.0;
  return out;
}

CircleRun run_circle(const EkfParams& params, double start_heading, double seconds, std::uint64_t seed) {
  CircleRun run(params);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> fix_noise(0.0, 0.04);
  std::normal_distribution<double> gyro_noise(0.0, 0.005);
  const double v = 0.2;
  const double omega = 0.2;  // radius 1 m
  Pose2 truth{1.5, 1.0, start_heading};
  const double dt = 1.0 / 70.0;
  for (int k = 0; k <= static_cast<int>(seconds * 70.0); ++k) {
    if (k > 0) {
      truth.x += v * dt * std::cos(truth.yaw + 0.5 * omega * dt);
      truth.y += v * dt * std::sin(truth.yaw + 0.5 * omega * dt);
      truth.yaw += omega * dt;
      run.ekf.predict(omega + gyro_noise(rng), dt);
      run.ekf.update_commanded({v, 0.0, omega});
    }
    if ((k * 20) % 70 < 20) {  // 20 of every 70 IMU ticks: 20 Hz
      const Vec2 antenna = fleet::geometry::body_to_map(truth, params.antenna_offset);
      Eigen::Matrix2d cov = 0.04 * 0.04 * Eigen::Matrix2d::Identity();
      run.ekf.update_uwb({antenna.x + fix_noise(rng), antenna.y + fix_noise(rng)}, cov);
    }
  }
  run.position_error = fleet::geometry::distance(run.ekf.pose().position(), truth.position());
  run.heading_error = std::abs(fleet::geometry::angle_diff(run.ekf.pose().yaw, truth.yaw));
  return run;
}

}  // namespace

TEST(EkfModels, MotionJacobianMatchesNumericalDerivative) {
  for (double theta : {0.0, 0.7, -2.4, 3.0}) {
    const StateVector x = some_state(theta);
    const double dt = 1.0 / 70.0;
    const double gyro = -0.2;
    const StateCovariance g = Ekf::motion_jacobian(x, dt);
    for (int j = 0; j < kStateSize; ++j) {
      const double h = 1e-6;
      StateVector xp = x;
      StateVector xm = x;
      xp(j) += h;
      xm(j) -= h;
      const StateVector col = (Ekf::motion_model(xp, gyro, dt) - Ekf::motion_model(xm, gyro, dt)) / (2.0 * h);
      for (int i = 0; i < kStateSize; ++i) EXPECT_NEAR(g(i, j), col(i), 1e-8) << "G(" << i << "," << j << ")";
    }
  }
}

TEST(EkfModels, MeasurementJacobianMatchesNumericalDerivative) {
  for (const Vec2 offset : {Vec2{0.05, 0.0}, Vec2{0.05, -0.02}}) {
    for (double theta : {0.0, 1.1, -2.9}) {
      const StateVector x = some_state(theta);
      const auto hm = Ekf::measurement_jacobian(x, offset);
      for (int j = 0; j < kStateSize; ++j) {
        const double h = 1e-6;
        StateVector xp = x;
        StateVector xm = x;
        xp(j) += h;
        xm(j) -= h;
        const Eigen::Vector2d col =
            (Ekf::measurement_model(xp, offset) - Ekf::measurement_model(xm, offset)) / (2.0 * h);
        EXPECT_NEAR(hm(0, j), col(0), 1e-9);
        EXPECT_NEAR(hm(1, j), col(1), 1e-9);
      }
    }
  }
}

TEST(EkfModels, MotionModelIsSeedEquation48) {
  StateVector x = some_state(0.5);
  x(kBias) = 0.0;  // no bias estimate: exactly eq. 4.8
  const double dt = 0.1;
  const StateVector y = Ekf::motion_model(x, 0.4, dt);
  EXPECT_NEAR(y(kX), x(kX) + x(kVx) * dt * std::cos(0.5) - x(kVy) * dt * std::sin(0.5), 1e-12);
  EXPECT_NEAR(y(kY), x(kY) + x(kVx) * dt * std::sin(0.5) + x(kVy) * dt * std::cos(0.5), 1e-12);
  EXPECT_NEAR(y(kTheta), 0.5 + 0.4 * dt, 1e-12);  // heading from the gyro, not the state's omega
  EXPECT_EQ(y(kOmega), x(kOmega));
  // With a bias estimate the heading integrates the corrected rate; the bias is a random walk.
  x(kBias) = 0.01;
  const StateVector yb = Ekf::motion_model(x, 0.4, dt);
  EXPECT_NEAR(yb(kTheta), 0.5 + (0.4 - 0.01) * dt, 1e-12);
  EXPECT_EQ(yb(kBias), 0.01);
  EXPECT_EQ(yb(kX), y(kX));
}

TEST(Ekf, InitialisesFromTheFirstFixLikeEquation414) {
  Ekf ekf(EkfParams::seed());
  EXPECT_FALSE(ekf.initialized());
  EXPECT_FALSE(ekf.predict(0.1, 0.01));
  EXPECT_EQ(ekf.score(), 0.0);
  EXPECT_EQ(ekf.update_uwb({1.05, 2.0}), UpdateStatus::kInitialized);
  EXPECT_TRUE(ekf.initialized());
  EXPECT_TRUE(ekf.heading_resolved());
  // Heading 0, so the body centre is 5 cm behind the antenna along x.
  EXPECT_NEAR(ekf.pose().x, 1.0, 1e-12);
  EXPECT_NEAR(ekf.pose().y, 2.0, 1e-12);
  EXPECT_EQ(ekf.pose().yaw, 0.0);
  EXPECT_EQ(ekf.velocity().vx, 0.0);
}

TEST(Ekf, NonFiniteInputsAreRejectedAndLeaveTheStateUntouched) {
  Ekf ekf(EkfParams::tuned());
  EXPECT_EQ(ekf.update_uwb({kNaN, 1.0}), UpdateStatus::kRejectedNonFinite);
  EXPECT_FALSE(ekf.initialized());
  ekf.update_uwb({1.0, 1.0});
  ekf.predict(0.0, 0.01);
  const StateVector x = ekf.state();
  const StateCovariance p = ekf.covariance();
  EXPECT_FALSE(ekf.predict(kNaN, 0.01));
  EXPECT_FALSE(ekf.predict(0.1, kInf));
  EXPECT_FALSE(ekf.predict(0.1, -0.01));
  EXPECT_EQ(ekf.update_uwb({1.0, kInf}), UpdateStatus::kRejectedNonFinite);
  Eigen::Matrix2d bad = Eigen::Matrix2d::Identity();
  bad(0, 1) = kNaN;
  EXPECT_EQ(ekf.update_uwb({1.0, 1.0}, bad), UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_commanded({kNaN, 0.0, 0.0}), UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.update_commanded({0.0, 0.0, -kInf}), UpdateStatus::kRejectedNonFinite);
  // A NaN gyro reading must not become the standstill bias measurement either.
  for (int i = 0; i < 10; ++i) EXPECT_FALSE(ekf.predict(kNaN, 0.1));
  EXPECT_EQ(ekf.state(), x);
  EXPECT_EQ(ekf.covariance(), p);
  ASSERT_TRUE(ekf.params().standstill_update);
  ekf.predict(0.0, 0.01);
  for (int i = 0; i < 40; ++i) {
    ekf.update_commanded({});
    ekf.predict(0.0, 0.01);
  }
  EXPECT_NE(ekf.update_commanded({}), UpdateStatus::kRejectedNonFinite);
  EXPECT_TRUE(ekf.state().allFinite());
  EXPECT_TRUE(ekf.covariance().allFinite());
  const StateVector x2 = ekf.state();
  const StateCovariance p2 = ekf.covariance();
  EXPECT_FALSE(ekf.predict(kInf, 0.01));
  EXPECT_EQ(ekf.update_commanded({kNaN, 0.0, 0.0}), UpdateStatus::kRejectedNonFinite);
  EXPECT_EQ(ekf.state(), x2);
  EXPECT_EQ(ekf.covariance(), p2);
}

TEST(Ekf, WithoutTheBiasStateTheBiasStaysExactlyZeroAndUncorrelated) {
  // The seed's six-state filter: b = 0 is a constant, never a random variable.
  EXPECT_FALSE(EkfParams::seed().gyro_bias);
  EXPECT_FALSE(EkfParams::seed().standstill_update);
  for (EkfParams p : {EkfParams::seed(), EkfParams::tuned()}) {
    p.gyro_bias = false;
    const CircleRun run = run_circle(p, 0.0, 10.0, 5);
    EXPECT_EQ(run.ekf.state()(kBias), 0.0);
    EXPECT_EQ(run.ekf.gyro_bias(), 0.0);
    EXPECT_TRUE(run.ekf.covariance().row(kBias).isZero(0.0));
    EXPECT_TRUE(run.ekf.covariance().col(kBias).isZero(0.0));
  }
}

TEST(Ekf, ConvergesFromInitialisation) {
  EkfParams p = EkfParams::tuned();
  const CircleRun run = run_circle(p, 0.0, 20.0, 1);
  EXPECT_LT(run.position_error, 0.04);
  EXPECT_LT(run.heading_error, 3.0 * kDeg);
  EXPECT_TRUE(run.ekf.heading_resolved());
  EXPECT_GT(run.ekf.score(), 0.5);
  EXPECT_LE(run.ekf.score(), 1.0);
  // The covariance has shrunk from the initial one.
  EXPECT_LT(run.ekf.covariance()(kX, kX), p.init_position_std * p.init_position_std);
}

TEST(Ekf, HeadingInitialisationRecoversANonZeroStartHeading) {
  for (double start : {2.0, -1.2, 3.0}) {
    EkfParams with = EkfParams::tuned();
    const CircleRun good = run_circle(with, start, 15.0, 2);
    EXPECT_LT(good.heading_error, 3.0 * kDeg) << "start " << start;
    EXPECT_LT(good.position_error, 0.05) << "start " << start;

    // The seed's assumption of heading 0 at start cannot recover the same quickly.
    EkfParams without = EkfParams::tuned();
    without.heading_init = false;
    without.gating = false;
    const CircleRun bad = run_circle(without, start, 3.0, 2);
    EXPECT_GT(bad.heading_error, 10.0 * kDeg) << "start " << start;
  }
}

TEST(Ekf, GatingRejectsAnOutlierAndRecoversAfterPersistentRejections) {
  EkfParams p = EkfParams::tuned();
  p.heading_init = false;
  p.velocity_source = VelocitySource::kNone;
  Ekf ekf(p);
  ekf.update_uwb({1.05, 1.0});
  for (int i = 0; i < 40; ++i) {
    ekf.predict(0.0, 1.0 / 70.0);
    if (i % 4 == 0) ekf.update_uwb({1.05, 1.0});
  }
  const StateVector before = ekf.state();
  EXPECT_EQ(ekf.update_uwb({2.05, 1.0}), UpdateStatus::kGated);
  EXPECT_EQ(ekf.state(), before);

  // Without gating the same fix drags the estimate.
  EkfParams open = p;
  open.gating = false;
  Ekf ungated(open);
  ungated.update_uwb({1.05, 1.0});
  EXPECT_EQ(ungated.update_uwb({2.05, 1.0}), UpdateStatus::kAccepted);
  EXPECT_GT(ungated.pose().x, 1.1);

  // If the robot really is elsewhere (kidnapped), the filter gives in after a few rejections.
  int accepted_at = -1;
  for (int i = 0; i < 3 * p.max_consecutive_rejections; ++i) {
    ekf.predict(0.0, 0.05);
    if (ekf.update_uwb({2.05, 1.0}) == UpdateStatus::kAccepted) {
      accepted_at = i;
      break;
    }
  }
  EXPECT_GE(accepted_at, 0);
  EXPECT_LE(accepted_at, p.max_consecutive_rejections);
  for (int i = 0; i < 60; ++i) {
    ekf.predict(0.0, 0.05);
    ekf.update_uwb({2.05, 1.0});
  }
  EXPECT_NEAR(ekf.pose().x, 2.0, 0.02);
}

TEST(Ekf, VelocityUpdatesFollowTheConfiguredSource) {
  EkfParams p = EkfParams::tuned();
  p.heading_init = false;
  Ekf ekf(p);
  EXPECT_EQ(ekf.update_commanded({0.2, 0.0, 0.0}), UpdateStatus::kNotInitialized);
  ekf.update_uwb({1.0, 1.0});
  EXPECT_EQ(ekf.update_encoders({0.2, 0.0, 0.0}), UpdateStatus::kIgnored);
  EXPECT_EQ(ekf.update_commanded({0.2, 0.0, 0.0}), UpdateStatus::kAccepted);
  EXPECT_GT(ekf.velocity().vx, 0.1);
  EkfParams seed = EkfParams::seed();
  Ekf s(seed);
  s.update_uwb({1.0, 1.0});
  EXPECT_EQ(s.update_commanded({0.2, 0.0, 0.0}), UpdateStatus::kIgnored);
}

TEST(Ekf, ScoreDropsWhenInnovationsAreInconsistent) {
  EkfParams p = EkfParams::tuned();
  p.heading_init = false;
  p.gating = false;
  Ekf calm(p);
  Ekf jumpy(p);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> small(0.0, 0.02);
  std::normal_distribution<double> large(0.0, 0.5);
  calm.update_uwb({1.0, 1.0});
  jumpy.update_uwb({1.0, 1.0});
  const Eigen::Matrix2d cov = 0.02 * 0.02 * Eigen::Matrix2d::Identity();
  for (int i = 0; i < 400; ++i) {
    calm.predict(0.0, 1.0 / 70.0);
    jumpy.predict(0.0, 1.0 / 70.0);
    calm.update_commanded({});
    jumpy.update_commanded({});
    if (i % 4 == 0) {
      calm.update_uwb({1.05 + small(rng), 1.0 + small(rng)}, cov);
      jumpy.update_uwb({1.05 + large(rng), 1.0 + large(rng)}, cov);
    }
  }
  EXPECT_GT(calm.score(), 0.4);
  EXPECT_LT(jumpy.score(), 0.5 * calm.score());
  EXPECT_GE(jumpy.score(), 0.0);
}

TEST(Ekf, RejectsInvalidParameters) {
  EkfParams p = EkfParams::tuned();
  p.uwb_std = 0.0;
  EXPECT_THROW(Ekf{p}, std::invalid_argument);
  p = EkfParams::tuned();
  p.process_noise[2] = -1e-6;
  EXPECT_THROW(Ekf{p}, std::invalid_argument);
  p = EkfParams::tuned();
  p.nominal_dt = kNaN;
  EXPECT_THROW(Ekf{p}, std::invalid_argument);
  EXPECT_NO_THROW(Ekf{EkfParams::seed()});
}

TEST(Ekf, WaitsForAValidFirstFix) {
  EkfParams p = EkfParams::tuned();
  Ekf ekf(p);
  // Ranges that disagree (NLOS) give the solver a wide covariance: not a fix to start from.
  EXPECT_EQ(ekf.update_uwb({1.0, 1.0}, 0.3 * 0.3 * Eigen::Matrix2d::Identity()), UpdateStatus::kNotInitialized);
  EXPECT_FALSE(ekf.initialized());
  EXPECT_EQ(ekf.update_uwb({1.0, 1.0}, 0.04 * 0.04 * Eigen::Matrix2d::Identity()), UpdateStatus::kInitialized);
  // The seed's filter takes any finite fix.
  Ekf seed(EkfParams::seed());
  EXPECT_EQ(seed.update_uwb({1.0, 1.0}, 0.3 * 0.3 * Eigen::Matrix2d::Identity()), UpdateStatus::kInitialized);
}

TEST(Ekf, StandstillUpdatesNeedAStoppedCommandForTheDelay) {
  EkfParams p = EkfParams::tuned();
  p.heading_init = false;
  p.velocity_source = VelocitySource::kNone;  // zero-velocity updates work without a velocity source
  Ekf ekf(p);
  EXPECT_EQ(ekf.update_standstill(), UpdateStatus::kNotInitialized);
  ekf.update_uwb({1.05, 1.0});
  EXPECT_EQ(ekf.update_commanded({0.1, 0.0, 0.0}), UpdateStatus::kIgnored);
  EXPECT_EQ(ekf.update_commanded({}), UpdateStatus::kIgnored);  // just stopped: wheels still turning
  const int steps = static_cast<int>(std::ceil(p.standstill_delay * 70.0)) + 1;
  for (int i = 0; i < steps; ++i) ekf.predict(0.0, 1.0 / 70.0);
  EXPECT_EQ(ekf.update_commanded({}), UpdateStatus::kAccepted);
  // Any motion command restarts the wait.
  EXPECT_EQ(ekf.update_commanded({0.0, 0.0, 0.1}), UpdateStatus::kIgnored);
  ekf.predict(0.0, 1.0 / 70.0);
  EXPECT_EQ(ekf.update_commanded({}), UpdateStatus::kIgnored);

  // Off in the parameters: never applied.
  EkfParams off = p;
  off.standstill_update = false;
  Ekf plain(off);
  plain.update_uwb({1.05, 1.0});
  for (int i = 0; i < 2 * steps; ++i) {
    plain.predict(0.0, 1.0 / 70.0);
    EXPECT_EQ(plain.update_commanded({}), UpdateStatus::kIgnored);
  }
  EXPECT_EQ(plain.update_standstill(), UpdateStatus::kIgnored);
}

TEST(Ekf, StandstillReadsTheGyroBias) {
  // A gyro reading 0.004 rad/s at rest: after a few seconds of zero-velocity updates the bias
  // estimate is that rate and the heading no longer drifts.
  EkfParams p = EkfParams::tuned();
  p.heading_init = false;
  Ekf ekf(p);
  ekf.update_uwb({1.05, 1.0});
  std::mt19937_64 rng(9);
  std::normal_distribution<double> noise(0.0, 0.005);
  const double bias = 0.004;
  for (int k = 0; k < 5 * 70; ++k) {
    ekf.predict(bias + noise(rng), 1.0 / 70.0);
    ekf.update_commanded({});
    if (k % 4 == 0) ekf.update_uwb({1.05, 1.0});
  }
  EXPECT_NEAR(ekf.gyro_bias(), bias, 0.0008);
  const double yaw = ekf.pose().yaw;
  for (int k = 0; k < 10 * 70; ++k) {
    ekf.predict(bias + noise(rng), 1.0 / 70.0);
    ekf.update_commanded({});
  }
  // Uncorrected, 10 s at 4 mrad/s would turn the estimate by 2.3 degrees.
  EXPECT_LT(std::abs(fleet::geometry::angle_diff(ekf.pose().yaw, yaw)), 0.3 * kDeg);
}

TEST(Ekf, GyroBiasConvergesToTheSimulatedWanderingBias) {
  // Stop and go for 10 minutes, 20 s on the circle and 5 s at rest, with the simulated gyro's
  // random-walk bias (default rate; a larger start so that it is well away from 0). Each stop
  // re-reads it.
  fleet::sim::GyroParams g;
  g.bias_initial_std = 0.004;
  EkfParams p = EkfParams::tuned();
  p.heading_init = false;
  p.gyro_bias_random_walk = g.bias_random_walk;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const StopAndGo r = run_stop_and_go(p, g, 20.0, 5.0, 600.0, seed);
    ASSERT_GE(r.bias_error_at_stop_end.size(), 20u);
    double sq = 0.0;
    for (std::size_t i = 2; i < r.bias_error_at_stop_end.size(); ++i) {
      sq += r.bias_error_at_stop_end[i] * r.bias_error_at_stop_end[i];
      // 5 s at rest, 350 readings of 5 mrad/s noise: about 0.3 mrad/s, plus the walk since.
      EXPECT_LT(std::abs(r.bias_error_at_stop_end[i]), 0.0012) << "seed " << seed << " stop " << i;
    }
    EXPECT_LT(std::sqrt(sq / static_cast<double>(r.bias_error_at_stop_end.size() - 2)), 0.0005) << "seed " << seed;

    // Without the bias state the same run keeps a larger heading error.
    EkfParams without = p;
    without.gyro_bias = false;
    without.standstill_update = false;
    const StopAndGo w = run_stop_and_go(without, g, 20.0, 5.0, 600.0, seed);
    EXPECT_LT(r.heading_rmse, 0.7 * w.heading_rmse) << "seed " << seed;
  }
}

TEST(Ekf, GyroBiasIsObservableFromUwbHeadingAlone) {
  // Never stopping, so only the heading corrections of the fixes inform the bias: a 5 mrad/s
  // offset (above the filter's initial 3 mrad/s) on top of the simulated gyro's own bias.
  fleet::sim::GyroParams g;
  g.bias_initial_std = 0.0005;
  g.bias_random_walk = 5.0e-5;
  EkfParams p = EkfParams::tuned();
  p.heading_init = false;
  p.standstill_update = false;
  for (std::uint64_t seed : {4u, 5u, 6u}) {
    const StopAndGo r = run_stop_and_go(p, g, 1.0, 0.0, 300.0, seed, 0.005);
    ASSERT_GT(std::abs(r.true_bias_final), 0.003);
    EXPECT_LT(std::abs(r.final_bias_error), 0.0015) << "seed " << seed << " true bias " << r.true_bias_final;
  }
}
