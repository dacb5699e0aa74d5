#include "sim/tricycle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

using namespace fleet::sim;
using fleet::geometry::Pose2;

namespace {

constexpr double kPi = std::numbers::pi;

/// No lag, no rate or acceleration limit: the wheel does what it is told at once.
TricycleParams ideal() {
  TricycleParams p;
  p.drive_time_constant = 0.0;
  p.steer_time_constant = 0.0;
  p.max_steer_rate = 1e6;
  p.max_wheel_acceleration = 1e6;
  return p;
}

}  // namespace

TEST(TricycleKinematics, ForwardMatchesTheSeedsEquations) {
  const TricycleRates r = forward_kinematics({0.5, 0.3}, 1.3);
  EXPECT_NEAR(r.v, 0.5 * std::cos(0.3), 1e-12);
  EXPECT_NEAR(r.yaw_rate, 0.5 / 1.3 * std::sin(0.3), 1e-12);
}

TEST(TricycleKinematics, InverseUndoesForwardBothWays) {
  for (double v : {0.4, -0.4}) {
    for (double w : {0.3, -0.3, 0.0}) {
      const TricycleCommand c = inverse_kinematics({v, w}, 1.3);
      const TricycleRates r = forward_kinematics(c, 1.3);
      EXPECT_NEAR(r.v, v, 1e-12) << v << " " << w;
      EXPECT_NEAR(r.yaw_rate, w, 1e-12) << v << " " << w;
      EXPECT_LE(std::abs(c.theta_steer), kPi / 2.0);
      EXPECT_NEAR(std::abs(c.v_steer), std::hypot(v, w * 1.3), 1e-12);  // [eq. 5.16]
    }
  }
  // Reversing turns the wheel the other way for the same yaw rate.
  EXPECT_LT(inverse_kinematics({-0.4, 0.3}, 1.3).theta_steer, 0.0);
  EXPECT_LT(inverse_kinematics({-0.4, 0.3}, 1.3).v_steer, 0.0);
}

TEST(TricycleKinematics, StandingStillTurningIsThePivot) {
  const TricycleCommand c = inverse_kinematics({0.0, -0.2}, 1.3);
  EXPECT_NEAR(c.theta_steer, -kPi / 2.0, 1e-12);
  EXPECT_NEAR(c.v_steer, 0.26, 1e-12);
  const TricycleRates r = forward_kinematics(c, 1.3);
  EXPECT_NEAR(r.v, 0.0, 1e-12);
  EXPECT_NEAR(r.yaw_rate, -0.2, 1e-12);
  EXPECT_EQ(inverse_kinematics({0.0, 0.0}, 1.3), (TricycleCommand{0.0, 0.0}));
}

TEST(Tricycle, PivotsAboutTheRearAxleMidpoint) {
  Tricycle t(ideal(), {2.0, 1.0, 0.0});
  t.step({0.0, kPi / 2.0}, 0.1);  // turn the wheel first
  const double v = 0.26;          // phi' = 0.2 rad/s
  t.step({v, kPi / 2.0}, kPi / 2.0 / 0.2);
  EXPECT_NEAR(t.pose().x, 2.0, 1e-9);
  EXPECT_NEAR(t.pose().y, 1.0, 1e-9);
  EXPECT_NEAR(t.pose().yaw, kPi / 2.0, 1e-6);
}

TEST(Tricycle, IntegratesArcsExactly) {
  Tricycle t(ideal(), {0.0, 0.0, 0.0});
  const double theta = 0.4;
  t.step({0.0, theta}, 0.1);
  const TricycleCommand c{0.5, theta};
  const TricycleRates r = forward_kinematics(c, t.params().geometry.wheelbase);
  const double radius = r.v / r.yaw_rate;
  t.step(c, (kPi / 2.0) / r.yaw_rate);  // a quarter circle
  EXPECT_NEAR(t.pose().x, radius, 1e-9);
  EXPECT_NEAR(t.pose().y, radius, 1e-9);
  EXPECT_NEAR(t.pose().yaw, kPi / 2.0, 1e-9);
}

TEST(Tricycle, ReversingWithTheInverseKinematicsTurnsTheAskedWay) {
  Tricycle t(ideal(), {});
  const TricycleCommand c = inverse_kinematics({-0.3, 0.2}, t.params().geometry.wheelbase);
  for (int i = 0; i < 20; ++i) t.step(c, 0.05);
  EXPECT_NEAR(t.pose().yaw, 0.2, 1e-6);
  EXPECT_LT(t.pose().x, 0.0);
}

TEST(Tricycle, SteeringIsLimitedInAngleAndRate) {
  TricycleParams p;
  p.steer_time_constant = 0.0;
  Tricycle t(p, {});
  t.step({0.0, 3.0}, 0.1);
  EXPECT_NEAR(t.held_command().theta_steer, kPi / 2.0, 1e-12);
  EXPECT_NEAR(t.state().theta_steer, p.max_steer_rate * 0.1, 1e-9);
  t.step(5.0);
  EXPECT_NEAR(t.state().theta_steer, kPi / 2.0, 1e-9);
}

TEST(Tricycle, DriveFollowsAFirstOrderLagAndTheAccelerationLimit) {
  TricycleParams p;
  p.max_wheel_acceleration = 1e6;
  Tricycle lagged(p, {});
  lagged.step({0.5, 0.0}, p.drive_time_constant);
  EXPECT_NEAR(lagged.state().v_steer, 0.5 * (1.0 - std::exp(-1.0)), 1e-9);

  TricycleParams q;
  q.drive_time_constant = 0.0;
  Tricycle limited(q, {});
  limited.step({2.0, 0.0}, 0.5);
  EXPECT_NEAR(limited.state().v_steer, q.max_wheel_acceleration * 0.5, 1e-9);
  // Distance under constant acceleration from rest.
  EXPECT_NEAR(limited.pose().x, 0.5 * q.max_wheel_acceleration * 0.25, 1e-9);
  limited.step({9.0, 0.0}, 10.0);
  EXPECT_NEAR(limited.state().v_steer, q.max_wheel_speed, 1e-9);
}

TEST(Tricycle, NonFiniteCommandStopsAndBadDtIsIgnored) {
  Tricycle t(ideal(), {});
  t.step({0.5, 0.2}, 1.0);
  const Pose2 before = t.pose();
  t.step(std::numeric_limits<double>::quiet_NaN());
  t.step(-1.0);
  EXPECT_EQ(t.pose(), before);
  t.step({std::numeric_limits<double>::infinity(), 0.0}, 0.1);
  EXPECT_EQ(t.state().v_steer, 0.0);
  EXPECT_NEAR(t.state().theta_steer, 0.2, 1e-12);
}

TEST(Tricycle, RejectsBadParameters) {
  TricycleParams p;
  p.geometry.wheelbase = 0.0;
  EXPECT_THROW(Tricycle(p, {}), std::invalid_argument);
  TricycleParams q;
  q.max_steer_angle = 2.0;
  EXPECT_THROW(Tricycle(q, {}), std::invalid_argument);
}

TEST(TricycleGeometry, FootprintHasTheForksBehindTheReferencePoint) {
  const TricycleGeometry g;
  const fleet::geometry::Polygon f = tricycle_footprint(g);
  const fleet::geometry::Bounds b = fleet::geometry::bounding_box(f);
  EXPECT_NEAR(b.max_x - b.min_x, 1.700, 1e-12);
  EXPECT_NEAR(b.max_y - b.min_y, 0.748, 1e-12);
  EXPECT_NEAR(b.min_x, -g.rear_overhang, 1e-12);
  const double chassis = (g.front_x() - g.chassis_back_x()) * g.width;
  const double forks = 2.0 * g.fork_length * g.fork_width;
  EXPECT_NEAR(fleet::geometry::signed_area(f), chassis + forks, 1e-9);     // counter-clockwise, no overlap
  EXPECT_TRUE(fleet::geometry::contains(f, {0.0, g.fork_spacing / 2.0}));  // on the left fork
  EXPECT_FALSE(fleet::geometry::contains(f, {0.0, 0.0}));                  // between the forks
  EXPECT_TRUE(fleet::geometry::contains(f, {g.drive_wheel_x(), 0.0}));     // the drive wheel is under the chassis
  // The forks fit the EPAL pockets with clearance on both sides.
  EXPECT_LT(g.fork_width, 0.2275);
  EXPECT_NEAR(g.fork_spacing, 0.3725, 0.02);
  // In the map, the docked stacker (yaw = pallet yaw) has its fork tips behind it.
  const Pose2 docked{0.0, 0.0, kPi / 2.0};
  EXPECT_NEAR(fork_tip_midpoint(docked, g).y, -g.rear_overhang, 1e-12);
}
