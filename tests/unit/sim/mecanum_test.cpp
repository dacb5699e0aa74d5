#include "sim/mecanum.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace fleet::sim;

TEST(Mecanum, InverseThenForwardReturnsTheTwist) {
  const MecanumKinematics kin;
  for (const BodyTwist t : {BodyTwist{0.2, 0.0, 0.0}, BodyTwist{0.0, -0.1, 0.0}, BodyTwist{0.0, 0.0, 0.8},
                            BodyTwist{0.12, 0.05, -0.4}, BodyTwist{-0.07, 0.11, 0.3}}) {
    const BodyTwist back = kin.forward(kin.inverse(t));
    EXPECT_NEAR(back.vx, t.vx, 1e-12);
    EXPECT_NEAR(back.vy, t.vy, 1e-12);
    EXPECT_NEAR(back.omega, t.omega, 1e-12);
  }
}

TEST(Mecanum, InverseMatchesSeedEquation61) {
  const MecanumParams p{0.03, 0.08, 0.06, 10.0};
  const MecanumKinematics kin(p);
  const BodyTwist t{0.1, 0.05, 0.5};
  const WheelSpeeds w = kin.inverse(t);
  const double l = p.half_wheelbase + p.half_track;
  EXPECT_NEAR(w[0], (t.vx - t.vy - l * t.omega) / p.wheel_radius, 1e-12);
  EXPECT_NEAR(w[1], (t.vx + t.vy + l * t.omega) / p.wheel_radius, 1e-12);
  EXPECT_NEAR(w[2], (t.vx + t.vy - l * t.omega) / p.wheel_radius, 1e-12);
  EXPECT_NEAR(w[3], (t.vx - t.vy + l * t.omega) / p.wheel_radius, 1e-12);
}

TEST(Mecanum, SaturationScalesAllWheelsAndKeepsTheDirection) {
  const MecanumKinematics kin;
  const BodyTwist fast{1.0, 0.5, 0.0};  // far beyond the 0.3 m/s servo limit
  const WheelSpeeds w = kin.saturate(kin.inverse(fast));
  double peak = 0.0;
  for (double s : w) peak = std::max(peak, std::abs(s));
  EXPECT_NEAR(peak, kin.params().max_wheel_speed, 1e-9);
  const BodyTwist limited = kin.forward(w);
  EXPECT_NEAR(limited.vy / limited.vx, 0.5, 1e-9);
  EXPECT_NEAR(kin.limits().max_linear, 0.3, 1e-12);
  EXPECT_NEAR(kin.limits().max_angular, 0.3 / 0.14, 1e-12);
  // A feasible command passes unchanged.
  const BodyTwist slow{0.1, 0.0, 0.2};
  const BodyTwist same = kin.limit(slow);
  EXPECT_NEAR(same.vx, slow.vx, 1e-12);
  EXPECT_NEAR(same.omega, slow.omega, 1e-12);
}

TEST(Mecanum, RejectsNonPositiveGeometry) {
  EXPECT_THROW(MecanumKinematics(MecanumParams{0.0, 0.08, 0.06, 10.0}), std::invalid_argument);
  EXPECT_THROW(MecanumKinematics(MecanumParams{0.03, 0.08, 0.06, -1.0}), std::invalid_argument);
}
