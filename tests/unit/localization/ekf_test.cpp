#include "localization/ekf.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

using namespace fleet::localization;
using fleet::geometry::Pose2;
using fleet::geometry::Vec2;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kDeg = std::numbers::pi / 180.0;

StateVector some_state(double theta) {
  StateVector x;
  x << 1.2, 0.7, theta, 0.18, -0.04, 0.3;
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
    for (int j = 0; j < 6; ++j) {
      const double h = 1e-6;
      StateVector xp = x;
      StateVector xm = x;
      xp(j) += h;
      xm(j) -= h;
      const StateVector col = (Ekf::motion_model(xp, gyro, dt) - Ekf::motion_model(xm, gyro, dt)) / (2.0 * h);
      for (int i = 0; i < 6; ++i) EXPECT_NEAR(g(i, j), col(i), 1e-8) << "G(" << i << "," << j << ")";
    }
  }
}

TEST(EkfModels, MeasurementJacobianMatchesNumericalDerivative) {
  for (const Vec2 offset : {Vec2{0.05, 0.0}, Vec2{0.05, -0.02}}) {
    for (double theta : {0.0, 1.1, -2.9}) {
      const StateVector x = some_state(theta);
      const auto hm = Ekf::measurement_jacobian(x, offset);
      for (int j = 0; j < 6; ++j) {
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
  const StateVector x = some_state(0.5);
  const double dt = 0.1;
  const StateVector y = Ekf::motion_model(x, 0.4, dt);
  EXPECT_NEAR(y(kX), x(kX) + x(kVx) * dt * std::cos(0.5) - x(kVy) * dt * std::sin(0.5), 1e-12);
  EXPECT_NEAR(y(kY), x(kY) + x(kVx) * dt * std::sin(0.5) + x(kVy) * dt * std::cos(0.5), 1e-12);
  EXPECT_NEAR(y(kTheta), 0.5 + 0.4 * dt, 1e-12);  // heading from the gyro, not the state's omega
  EXPECT_EQ(y(kOmega), x(kOmega));
}

TEST(Ekf, InitialisesFromTheFirstFixLikeEquation414) {
  Ekf ekf(EkfParams::seed());
  EXPECT_FALSE(ekf.initialized());
  EXPECT_FALSE(ekf.predict(0.1, 0.01));
  EXPECT_EQ(ekf.score(), 0.0);
  EXPECT_EQ(ekf.update_uwb({1.05, 2.0}), UpdateStatus::initialized);
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
  EXPECT_EQ(ekf.update_uwb({kNaN, 1.0}), UpdateStatus::rejected_non_finite);
  EXPECT_FALSE(ekf.initialized());
  ekf.update_uwb({1.0, 1.0});
  ekf.predict(0.0, 0.01);
  const StateVector x = ekf.state();
  const StateCovariance p = ekf.covariance();
  EXPECT_FALSE(ekf.predict(kNaN, 0.01));
  EXPECT_FALSE(ekf.predict(0.1, kInf));
  EXPECT_FALSE(ekf.predict(0.1, -0.01));
  EXPECT_EQ(ekf.update_uwb({1.0, kInf}), UpdateStatus::rejected_non_finite);
  Eigen::Matrix2d bad = Eigen::Matrix2d::Identity();
  bad(0, 1) = kNaN;
  EXPECT_EQ(ekf.update_uwb({1.0, 1.0}, bad), UpdateStatus::rejected_non_finite);
  EXPECT_EQ(ekf.update_commanded({kNaN, 0.0, 0.0}), UpdateStatus::rejected_non_finite);
  EXPECT_EQ(ekf.update_commanded({0.0, 0.0, -kInf}), UpdateStatus::rejected_non_finite);
  EXPECT_EQ(ekf.state(), x);
  EXPECT_EQ(ekf.covariance(), p);
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
  p.velocity_source = VelocitySource::none;
  Ekf ekf(p);
  ekf.update_uwb({1.05, 1.0});
  for (int i = 0; i < 40; ++i) {
    ekf.predict(0.0, 1.0 / 70.0);
    if (i % 4 == 0) ekf.update_uwb({1.05, 1.0});
  }
  const StateVector before = ekf.state();
  EXPECT_EQ(ekf.update_uwb({2.05, 1.0}), UpdateStatus::gated);
  EXPECT_EQ(ekf.state(), before);

  // Without gating the same fix drags the estimate.
  EkfParams open = p;
  open.gating = false;
  Ekf ungated(open);
  ungated.update_uwb({1.05, 1.0});
  EXPECT_EQ(ungated.update_uwb({2.05, 1.0}), UpdateStatus::accepted);
  EXPECT_GT(ungated.pose().x, 1.1);

  // If the robot really is elsewhere (kidnapped), the filter gives in after a few rejections.
  int accepted_at = -1;
  for (int i = 0; i < 3 * p.max_consecutive_rejections; ++i) {
    ekf.predict(0.0, 0.05);
    if (ekf.update_uwb({2.05, 1.0}) == UpdateStatus::accepted) {
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
  EXPECT_EQ(ekf.update_commanded({0.2, 0.0, 0.0}), UpdateStatus::not_initialized);
  ekf.update_uwb({1.0, 1.0});
  EXPECT_EQ(ekf.update_encoders({0.2, 0.0, 0.0}), UpdateStatus::ignored);
  EXPECT_EQ(ekf.update_commanded({0.2, 0.0, 0.0}), UpdateStatus::accepted);
  EXPECT_GT(ekf.velocity().vx, 0.1);
  EkfParams seed = EkfParams::seed();
  Ekf s(seed);
  s.update_uwb({1.0, 1.0});
  EXPECT_EQ(s.update_commanded({0.2, 0.0, 0.0}), UpdateStatus::ignored);
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
  EXPECT_EQ(ekf.update_uwb({1.0, 1.0}, 0.3 * 0.3 * Eigen::Matrix2d::Identity()), UpdateStatus::not_initialized);
  EXPECT_FALSE(ekf.initialized());
  EXPECT_EQ(ekf.update_uwb({1.0, 1.0}, 0.04 * 0.04 * Eigen::Matrix2d::Identity()), UpdateStatus::initialized);
  // The seed's filter takes any finite fix.
  Ekf seed(EkfParams::seed());
  EXPECT_EQ(seed.update_uwb({1.0, 1.0}, 0.3 * 0.3 * Eigen::Matrix2d::Identity()), UpdateStatus::initialized);
}
