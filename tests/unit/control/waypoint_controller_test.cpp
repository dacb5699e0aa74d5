#include "control/waypoint_controller.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include "sim/encoders.hpp"
#include "sim/forklift_body.hpp"
#include "sim/mecanum.hpp"
#include "sim/summit_xls.hpp"

using fleet::control::speed_saturation;
using fleet::control::turn_speed_scale;
using fleet::control::waypoint_errors;
using fleet::control::WaypointController;
using fleet::control::WaypointControllerParams;
using fleet::geometry::Pose2;
using fleet::geometry::Vec2;

namespace {

constexpr double kPi = std::numbers::pi;

fleet::sim::ForkliftParams summit_no_slip() {
  fleet::sim::ForkliftParams p = fleet::sim::summit_xls_body_params();
  p.slip_std = 0.0;
  return p;
}

/// Seed wheel order (front-right, front-left, rear-left, rear-right [Picker thesis, eq. 3.5, Fig. 3.4]) to the
/// MecanumKinematics order (front-left, front-right, rear-left, rear-right).
constexpr std::array<int, 4> kSeedToRepo{1, 0, 2, 3};

struct LoopResult {
  Pose2 truth;
  Pose2 odometry;
  double time = 0.0;
  bool done = false;
  double max_speed = 0.0;
};

/// The controller on encoder odometry [eq. 3.7] driving the simulated Summit-XLS until it stops or `limit` s pass.
LoopResult run_loop(const std::vector<Vec2>& waypoints, const Pose2& start, const WaypointControllerParams& cp,
                    double slip_std, std::uint64_t seed, double limit = 120.0) {
  fleet::sim::ForkliftParams bp = fleet::sim::summit_xls_body_params();
  bp.slip_std = slip_std;
  fleet::sim::ForkliftBody body(bp, start, std::mt19937_64(seed));
  fleet::sim::WheelEncoders encoders(fleet::sim::summit_xls_encoder_params(), std::mt19937_64(seed + 1));
  fleet::sim::WheelOdometry odometry(bp.mecanum, start);
  WaypointController controller(cp);
  controller.set_waypoints(waypoints);
  LoopResult r;
  for (; r.time < limit && !controller.done(); r.time += cp.period) {
    const fleet::control::BodyTwist cmd = controller.update(odometry.pose());
    body.step({cmd.vx, cmd.vy, cmd.omega}, cp.period);
    odometry.update(encoders.measure(body.wheel_speeds(), cp.period), cp.period);
    r.max_speed = std::max(r.max_speed, std::hypot(body.twist().vx, body.twist().vy));
  }
  // Let the base come to rest after the last (zero) command.
  for (int i = 0; i < 50; ++i) {
    body.step({}, cp.period);
    odometry.update(encoders.measure(body.wheel_speeds(), cp.period), cp.period);
  }
  r.truth = body.pose();
  r.odometry = odometry.pose();
  r.done = controller.done();
  return r;
}

}  // namespace

TEST(SummitXls, InverseKinematicsOfEq35AndForwardOfEq37InvertEachOther) {
  const fleet::sim::MecanumParams p = fleet::sim::summit_xls_body_params().mecanum;
  const double r = p.wheel_radius;
  const double ab = p.half_wheelbase + p.half_track;  // a + b
  // [Picker thesis, eq. 3.5-3.6] and [eq. 3.7] as printed, seed wheel order.
  const double J[4][3] = {{1, 1, ab}, {1, -1, -ab}, {1, 1, -ab}, {1, -1, ab}};
  const double Jp[3][4] = {{1, 1, 1, 1}, {1, -1, 1, -1}, {1 / ab, -1 / ab, -1 / ab, 1 / ab}};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double s = 0.0;
      for (int k = 0; k < 4; ++k) s += (r / 4.0) * Jp[i][k] * (J[k][j] / r);
      EXPECT_NEAR(s, i == j ? 1.0 : 0.0, 1e-12) << i << "," << j;  // J⁺·J = I
    }
  }
  const fleet::sim::MecanumKinematics kin(p);
  const std::array<fleet::sim::BodyTwist, 4> twists{
      {{0.3, 0.0, 0.0}, {0.0, -0.2, 0.0}, {0.1, 0.2, 0.5}, {-1, 0.4, -2}}};
  for (const fleet::sim::BodyTwist& t : twists) {
    const fleet::sim::WheelSpeeds w = kin.inverse(t);
    for (int i = 0; i < 4; ++i) {
      const double seed = (J[i][0] * t.vx + J[i][1] * t.vy + J[i][2] * t.omega) / r;
      EXPECT_NEAR(w[static_cast<std::size_t>(kSeedToRepo[static_cast<std::size_t>(i)])], seed, 1e-12);
    }
    const fleet::sim::BodyTwist back = kin.forward(w);
    EXPECT_NEAR(back.vx, t.vx, 1e-12);
    EXPECT_NEAR(back.vy, t.vy, 1e-12);
    EXPECT_NEAR(back.omega, t.omega, 1e-12);
  }
  // Four wheels, three degrees of freedom: inverse(forward(w)) drops only the wheels' fight (1, 1, −1, −1) (seed
  // order), which moves nothing.
  const fleet::sim::WheelSpeeds fight_seed{1, 1, -1, -1};
  fleet::sim::WheelSpeeds fight{};
  for (int i = 0; i < 4; ++i)
    fight[static_cast<std::size_t>(kSeedToRepo[static_cast<std::size_t>(i)])] = fight_seed[static_cast<std::size_t>(i)];
  const fleet::sim::BodyTwist none = kin.forward(fight);
  EXPECT_NEAR(std::abs(none.vx) + std::abs(none.vy) + std::abs(none.omega), 0.0, 1e-12);
  const fleet::sim::WheelSpeeds w{2.0, -1.0, 0.5, 3.0};
  const fleet::sim::WheelSpeeds round = kin.inverse(kin.forward(w));
  double along = 0.0;
  for (int i = 0; i < 4; ++i) along += w[static_cast<std::size_t>(i)] * fight[static_cast<std::size_t>(i)] / 4.0;
  for (int i = 0; i < 4; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_NEAR(round[k], w[k] - along * fight[k], 1e-12);
  }
}

TEST(SummitXls, GeometryFitsTheSeedsBaseAndTopSpeed) {
  const fleet::sim::ForkliftParams p = fleet::sim::summit_xls_body_params();
  const fleet::sim::MecanumParams& m = p.mecanum;
  EXPECT_LE(m.half_wheelbase + m.wheel_radius, 0.65 / 2.0);  // the 0.65 m length includes the wheels [3.1.1]
  EXPECT_LT(m.half_track, 0.50 / 2.0);
  EXPECT_NEAR(2.0 * m.wheel_radius, 0.254, 1e-9);
  EXPECT_NEAR(fleet::sim::MecanumKinematics(m).limits().max_linear, fleet::sim::SummitXlsSpeeds::kTop, 1e-9);
  EXPECT_TRUE(fleet::sim::summit_xls_encoder_params().enabled);
}

// [Picker thesis, section 4.3.2.1, Fig. 4.27]: a 0.3 m/s step "reaches the final value in almost 0.3 seconds" and
// stays within ±2 %.
TEST(SummitXls, StepOfThreeTenthsMetrePerSecondSettlesInAboutThreeTenthsOfASecond) {
  fleet::sim::ForkliftBody body(summit_no_slip(), {}, std::mt19937_64(1));
  const double step = 0.3;
  const double dt = 0.001;
  double settled = 0.0;  // the last time the speed was outside ±2 % of the step
  double t = 0.0;
  for (int i = 0; i < 1000; ++i) {
    body.step({step, 0.0, 0.0}, dt);
    t += dt;
    if (std::abs(body.twist().vx - step) > 0.02 * step) settled = t;
  }
  std::printf("[ measured ] 0.3 m/s step, ±2 %% settling: %.3f s (seed, Fig. 4.27: ~0.3 s)\n", settled);
  EXPECT_NEAR(settled, 0.3, 0.05);
  EXPECT_NEAR(body.twist().vx, step, 1e-6);  // no steady-state error
}

TEST(WaypointController, ErrorsOfEq410To412UseTheFullBearing) {
  // Robot at (1, 1) facing +y; a waypoint 2 m ahead.
  auto e = waypoint_errors({1.0, 1.0, kPi / 2.0}, {1.0, 3.0}, 0.5);
  EXPECT_NEAR(e.x_wr, 2.0, 1e-12);
  EXPECT_NEAR(e.y_wr, 0.0, 1e-12);
  EXPECT_NEAR(e.alpha, 0.0, 1e-12);
  EXPECT_NEAR(e.e_x, 1.5, 1e-12);
  EXPECT_NEAR(e.e_y, 0.0, 1e-12);
  // One on the robot's right: Y_WR < 0.
  e = waypoint_errors({1.0, 1.0, kPi / 2.0}, {2.0, 1.0}, 0.0);
  EXPECT_NEAR(e.alpha, -kPi / 2.0, 1e-12);
  EXPECT_NEAR(e.e_y, -1.0, 1e-12);
  // Behind: atan(Y/X) would give α = 0 and drive away; atan2 gives π and e_X < 0.
  e = waypoint_errors({0.0, 0.0, 0.0}, {-2.0, 0.0}, 0.0);
  EXPECT_NEAR(std::abs(e.alpha), kPi, 1e-12);
  EXPECT_NEAR(e.e_x, -2.0, 1e-12);
  EXPECT_NEAR(e.ge, 2.0, 1e-12);
}

TEST(WaypointController, SpeedSaturationAndTurnScale) {
  EXPECT_NEAR(speed_saturation(0.25, 0.3, 0.5), 0.15, 1e-12);  // ramp within D_XM
  EXPECT_NEAR(speed_saturation(5.0, 0.3, 0.5), 0.3, 1e-12);    // U_M beyond
  EXPECT_NEAR(speed_saturation(-5.0, 0.3, 0.5), -0.3, 1e-12);
  EXPECT_NEAR(speed_saturation(0.0, 0.3, 0.5), 0.0, 1e-12);
  EXPECT_NEAR(turn_speed_scale(0.0), 1.0, 1e-12);
  EXPECT_NEAR(turn_speed_scale(kPi / 2.0), 0.0, 1e-12);
  EXPECT_NEAR(turn_speed_scale(-kPi / 2.0), 0.0, 1e-12);  // the printed |1 − sin α| would give 2
  EXPECT_NEAR(turn_speed_scale(kPi / 6.0), turn_speed_scale(-kPi / 6.0), 1e-12);
  EXPECT_NEAR(turn_speed_scale(kPi / 6.0), 0.5, 1e-12);
}

TEST(WaypointController, ForwardSpeedIsFilteredAndSaturated) {
  WaypointControllerParams p;  // T = 0.02, τ_u = 0.1, U_M = 0.3
  WaypointController c(p);
  c.set_waypoints({{10.0, 0.0}});
  const double a = p.tau_u / (p.period + p.tau_u);
  double expected = 0.0;
  for (int i = 0; i < 200; ++i) {
    const auto t = c.update({0.0, 0.0, 0.0});
    expected = a * expected + (1.0 - a) * p.max_speed;  // [eq. 4.15]
    ASSERT_NEAR(t.vx, expected, 1e-12) << i;
    ASSERT_LE(t.vx, p.max_speed + 1e-12);
    EXPECT_EQ(t.vy, 0.0);
    EXPECT_EQ(t.omega, 0.0);
  }
  EXPECT_NEAR(c.update({0.0, 0.0, 0.0}).vx, p.max_speed, 1e-9);
}

TEST(WaypointController, YawRateIsCappedAndFiltered) {
  WaypointControllerParams p;  // K_Y = 1.5, cap 0.6 rad/s, τ_r = 0.1
  const double b = p.period / (p.period + p.tau_r);
  {
    // Far on the left: K_Y·d = 7.5 is capped at 0.6; no forward speed at α = π/2.
    WaypointController c(p);
    c.set_waypoints({{0.0, 5.0}});
    auto t = c.update({0.0, 0.0, 0.0});
    EXPECT_NEAR(t.omega, b * p.max_omega, 1e-12);
    EXPECT_NEAR(t.vx, 0.0, 1e-12);
    for (int i = 0; i < 300; ++i) {
      t = c.update({0.0, 0.0, 0.0});
      ASSERT_LE(t.omega, p.max_omega + 1e-12);
    }
    EXPECT_NEAR(t.omega, p.max_omega, 1e-9);
  }
  {
    // Near on the right: K_Y·d = 0.3 is below the cap, so ω → −K_Y·d·sin(π/2) [eq. 4.16].
    WaypointController c(p);
    c.set_waypoints({{0.0, -0.2}});
    fleet::control::BodyTwist t;
    for (int i = 0; i < 300; ++i) t = c.update({0.0, 0.0, 0.0});
    EXPECT_NEAR(t.omega, -p.k_y * 0.2, 1e-9);
  }
}

TEST(WaypointController, StopsAtTheLastWaypointAndRejectsBadParams) {
  WaypointController c;
  c.set_waypoints({{1.0, 0.0}, {1.01, 0.0}});
  const auto t = c.update({1.0, 0.0, 0.0});  // both within tolerance already
  EXPECT_TRUE(c.done());
  EXPECT_EQ(t.vx, 0.0);
  EXPECT_EQ(t.omega, 0.0);
  c.set_waypoints({});
  EXPECT_TRUE(c.done());
  WaypointControllerParams bad;
  bad.period = 0.0;
  EXPECT_THROW(WaypointController{bad}, std::invalid_argument);
}

// Closed loop on the simulated Summit-XLS, the controller fed by encoder odometry [eq. 3.7] as on the real robot
// [section 4.3.2.2], through a path with turns like the planner's waypoints.
TEST(WaypointController, DrivesTheSimulatedBaseThroughWaypoints) {
  const std::vector<Vec2> path{{2.0, 0.0}, {2.0, 1.5}, {0.5, 2.5}, {0.5, 4.0}};
  const WaypointControllerParams p;
  // Without slip the odometry is the truth up to the encoders' ticks and noise.
  const LoopResult exact = run_loop(path, {0.0, 0.0, 0.0}, p, 0.0, 5);
  ASSERT_TRUE(exact.done);
  const double err = std::hypot(exact.truth.x - path.back().x, exact.truth.y - path.back().y);
  std::printf("[ measured ] no slip: %.1f s, peak %.3f m/s, final error %.3f m (truth)\n", exact.time, exact.max_speed,
              err);
  EXPECT_LT(err, 0.04);
  EXPECT_LE(exact.max_speed, p.max_speed + 0.01);
  // With the 3 % roller slip the odometry drifts: the controller still stops on its estimate, the truth is off by
  // the drift.
  for (std::uint64_t seed : {11u, 12u, 13u}) {
    const LoopResult slip = run_loop(path, {0.0, 0.0, 0.0}, p, fleet::sim::summit_xls_body_params().slip_std, seed);
    ASSERT_TRUE(slip.done);
    const double est = std::hypot(slip.odometry.x - path.back().x, slip.odometry.y - path.back().y);
    const double truth = std::hypot(slip.truth.x - path.back().x, slip.truth.y - path.back().y);
    std::printf("[ measured ] 3 %% slip, seed %d: %.1f s, final error %.3f m odometry, %.3f m truth\n",
                static_cast<int>(seed), slip.time, est, truth);
    EXPECT_LT(est, 0.04);
    EXPECT_LT(truth, 0.05 * 6.8);  // the drift: within 5 % of the 6.8 m driven
  }
}

TEST(WaypointController, ReachesAWaypointBehindTheBase) {
  const WaypointControllerParams p;
  const LoopResult r = run_loop({{-1.5, 0.5}}, {0.0, 0.0, 0.0}, p, 0.0, 3, 60.0);
  ASSERT_TRUE(r.done);
  EXPECT_LT(std::hypot(r.truth.x + 1.5, r.truth.y - 0.5), 0.04);
}

// Fig. 4.29: closed-loop moves of 2 m and 6 m with U_M = 1 m/s; the long one reaches U_M, the short one does not
// stay there.
TEST(WaypointController, ClosedLoopMovesAtOneMetrePerSecond) {
  WaypointControllerParams p;
  p.max_speed = fleet::sim::SummitXlsSpeeds::kMaxTested;
  p.decel_distance = 1.5;
  for (double distance : {2.0, 6.0}) {
    const LoopResult r = run_loop({{distance, 0.0}}, {0.0, 0.0, 0.0}, p, 0.0, 7, 60.0);
    ASSERT_TRUE(r.done);
    std::printf("[ measured ] %.0f m move at U_M = 1 m/s: %.1f s, peak %.3f m/s, final error %.3f m\n", distance,
                r.time, r.max_speed, std::abs(r.truth.x - distance));
    EXPECT_LE(r.max_speed, 1.0 + 0.01);
    EXPECT_LT(std::abs(r.truth.x - distance), 0.04);
    if (distance > 5.0) {
      EXPECT_GT(r.max_speed, 0.95);
    }
  }
}
