#include "sim/forklift_body.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

using namespace fleet::sim;
using fleet::geometry::Pose2;

namespace {
ForkliftParams no_slip() {
  ForkliftParams p;
  p.slip_std = 0.0;
  return p;
}
}  // namespace

TEST(ForkliftBody, WheelsFollowTheCommandWithTheFirstOrderLag) {
  ForkliftBody body(no_slip(), {}, std::mt19937_64(1));
  const BodyTwist cmd{0.2, 0.0, 0.0};
  body.step(cmd, 0.02);  // one time constant
  EXPECT_NEAR(body.twist().vx, 0.2 * (1.0 - std::exp(-1.0)), 2e-3);
  body.step(cmd, 0.18);  // ten time constants in all
  EXPECT_NEAR(body.twist().vx, 0.2, 1e-5);
  // Distance after 2 s of a step command: v (t - tau) for a first-order lag.
  ForkliftBody b2(no_slip(), {}, std::mt19937_64(1));
  for (int i = 0; i < 200; ++i) b2.step(cmd, 0.01);
  EXPECT_NEAR(b2.pose().x, 0.2 * (2.0 - 0.02), 1e-4);
  EXPECT_NEAR(b2.pose().y, 0.0, 1e-12);
}

TEST(ForkliftBody, IntegratesArcsExactly) {
  ForkliftParams p = no_slip();
  p.wheel_time_constant = 0.0;
  ForkliftBody body(p, {1.0, 1.0, 0.0}, std::mt19937_64(1));
  // A quarter circle of radius 0.5 m at 0.2 m/s.
  const double omega = 0.4;
  const double t = (std::numbers::pi / 2.0) / omega;
  body.step({0.2, 0.0, omega}, t);
  EXPECT_NEAR(body.pose().x, 1.5, 1e-9);
  EXPECT_NEAR(body.pose().y, 1.5, 1e-9);
  EXPECT_NEAR(body.pose().yaw, std::numbers::pi / 2.0, 1e-9);
}

TEST(ForkliftBody, SlipIsReproducibleFromTheSeed) {
  ForkliftBody a(ForkliftParams{}, {}, std::mt19937_64(7));
  ForkliftBody b(ForkliftParams{}, {}, std::mt19937_64(7));
  ForkliftBody c(ForkliftParams{}, {}, std::mt19937_64(8));
  for (int i = 0; i < 500; ++i) {
    a.step({0.2, 0.0, 0.3}, 0.01);
    b.step({0.2, 0.0, 0.3}, 0.01);
    c.step({0.2, 0.0, 0.3}, 0.01);
  }
  EXPECT_EQ(a.pose(), b.pose());
  EXPECT_NE(a.pose(), c.pose());
}

TEST(ForkliftBody, NonFiniteCommandStopsAndBadDtIsIgnored) {
  ForkliftBody body(no_slip(), {}, std::mt19937_64(1));
  body.step({0.2, 0.0, 0.0}, 1.0);
  const Pose2 before = body.pose();
  body.step({0.2, 0.0, 0.0}, std::numeric_limits<double>::quiet_NaN());
  body.step({0.2, 0.0, 0.0}, -1.0);
  EXPECT_EQ(body.pose(), before);
  body.step({std::numeric_limits<double>::infinity(), 0.0, 0.0}, 1.0);
  EXPECT_NEAR(body.twist().vx, 0.0, 1e-9);
  EXPECT_TRUE(fleet::geometry::is_finite(body.pose()));
}

TEST(ForkliftBody, FootprintFollowsThePose) {
  ForkliftBody body(no_slip(), {1.0, 2.0, std::numbers::pi / 2.0}, std::mt19937_64(1));
  const auto poly = body.footprint_polygon();
  ASSERT_EQ(poly.size(), 4u);
  const auto box = fleet::geometry::bounding_box(poly);
  EXPECT_NEAR(box.max_y - box.min_y, 0.25, 1e-9);  // length now along map y
  EXPECT_NEAR(box.max_x - box.min_x, 0.16, 1e-9);
}
