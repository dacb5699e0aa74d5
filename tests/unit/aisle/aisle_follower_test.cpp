#include "aisle/aisle_follower.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "aisle/hough_lines.hpp"
#include "eval/aisle_eval.hpp"
#include "geometry/pose.hpp"
#include "sim/forklift_body.hpp"

using namespace fleet::aisle;
using fleet::geometry::Pose2;
using fleet::sim::BodyTwist;

namespace {

constexpr double kPi = std::numbers::pi;
using ::fleet::geometry::kDeg;
constexpr double kPeriod = 1.0 / 40.0;  // one control step per UST-10LX scan (40 Hz) [Picker thesis, Table 6]

/// A pair of rack lines as the detector would report it, parallel to the body x axis turned by `heading`.
RackLinePair pair_at(double left_distance, double right_distance, double heading) {
  RackLinePair pair;
  pair.status = PairStatus::kFound;
  pair.left = {heading + kPi / 2.0, left_distance, 200};
  pair.right = {heading + kPi / 2.0, -right_distance, 200};
  pair.heading = heading;
  pair.width = left_distance + right_distance;
  return pair;
}

// ---- closed loop (eval::run_aisle): the simulated mecanum body and lidars, the detector and the follower ---------

using fleet::eval::aisle_figures;
using fleet::eval::AisleFigures;
using fleet::eval::AisleRun;
using fleet::eval::PickerSetup;
using fleet::eval::PickerTrace;
using fleet::eval::run_aisle;
using fleet::eval::seed_aisle_case;
using fleet::eval::seed_aisle_setup;
using fleet::eval::SeedAisleCase;

void print_figures(const PickerTrace& t, const AisleFigures& f) {
  std::printf(
      "[aisle follow] %-28s settled (3 cm, 1 deg) %.2f s | lateral <5 cm %.2f s | heading <1 deg %.2f s | peak v %.3f "
      "u %.3f m/s r %.3f rad/s | final lateral %+.3f m heading %+.2f deg along %+.3f m | frames without pair %.1f %%\n",
      t.setup.name.c_str(), f.settle, f.lateral_5cm, f.heading_1deg, f.peak_lateral, f.peak_forward, f.peak_yaw_rate,
      f.final_lateral, f.final_heading / kDeg, f.final_along, 100.0 * f.lost_fraction);
}

}  // namespace

TEST(Sigmoid, IsTheSeedsSaturationAndOdd) {
  EXPECT_DOUBLE_EQ(sigmoid(0.0, 5.0), 0.0);
  const double z = 0.3;
  EXPECT_NEAR(sigmoid(z, 5.0), (1.0 - std::exp(-5.0 * z)) / (1.0 + std::exp(-5.0 * z)), 1e-12);
  EXPECT_NEAR(sigmoid(-z, 5.0), -sigmoid(z, 5.0), 1e-12);
  EXPECT_NEAR(sigmoid(1e6, 5.0), 1.0, 1e-12);
}

TEST(AisleErrors, FollowTheChosenFaceWithTheSignThatMovesTheBaseThere) {
  AisleFollowerParams right;
  // 1.5 m from each face, turned so that the aisle points 10 deg right of body x (the base is turned 10 deg left).
  const RackLinePair pair = pair_at(1.5, 1.5, -10.0 * kDeg);
  const AisleErrors r = aisle_errors(pair, 5.0, right);
  ASSERT_TRUE(r.valid()) << to_string(r.status);
  EXPECT_NEAR(r.side_distance, 1.5, 1e-12);
  EXPECT_NEAR(r.lateral, -0.5, 1e-12);  // d_ref 1 m from the right face: move right
  EXPECT_NEAR(r.heading, -10.0 * kDeg, 1e-12);
  EXPECT_DOUBLE_EQ(r.along, 5.0);

  AisleFollowerParams left = right;
  left.side = RackSide::kLeft;
  const AisleErrors l = aisle_errors(pair, 5.0, left);
  EXPECT_NEAR(l.lateral, 0.5, 1e-12);  // d_ref 1 m from the left face: move left
}

TEST(AisleErrors, OutsideTheirValidityLimitsTheyDoNotDrive) {
  AisleFollowerParams p;
  EXPECT_EQ(aisle_errors(pair_at(1.5, 1.5, 65.0 * kDeg), 0.0, p).status, AisleErrorStatus::kHeadingOutside);
  // |e_y| ≤ w_R / cos(e_θ): a 1 m reference 4.5 m from the face in a (mis-sized) 3 m aisle.
  EXPECT_EQ(aisle_errors(pair_at(0.5, 4.5, 0.0), 0.0, p).status, AisleErrorStatus::kLateralOutside);
  EXPECT_EQ(aisle_errors(RackLinePair{}, 0.0, p).status, AisleErrorStatus::kNoRackLines);
  EXPECT_EQ(to_string(AisleErrorStatus::kNoRackLines), "no rack lines");
}

TEST(AisleFollower, CommandsTheSeedsLawsThroughTheirFilters) {
  AisleFollowerParams p;
  AisleFollower follower(p);
  follower.start(5.0);
  const RackLinePair pair = pair_at(1.5, 1.5, -10.0 * kDeg);
  BodyTwist cmd;
  for (int i = 0; i < 40; ++i) cmd = follower.update(pair, BodyTwist{}, kPeriod);  // 1 s at rest: filters settled
  const double e_y = -0.5;
  const double e_t = -10.0 * kDeg;
  // [eq. 4.33-4.35]
  EXPECT_NEAR(cmd.vx, p.forward_speed * sigmoid(5.0, 5.0) * (1.0 - std::abs(e_y) / 3.0) * std::cos(e_t), 1e-9);
  EXPECT_NEAR(cmd.vy, p.lateral_speed * sigmoid(e_y, 5.0) * std::cos(e_t), 1e-9);
  EXPECT_NEAR(cmd.omega, p.yaw_rate * sigmoid(e_t, 5.0), 1e-9);
  EXPECT_LT(cmd.vy, 0.0);
  EXPECT_LT(cmd.omega, 0.0);

  // One step of the first-order filter from rest: T / (T + τ) of the target.
  AisleFollower fresh(p);
  fresh.start(5.0);
  const BodyTwist first = fresh.update(pair, BodyTwist{}, kPeriod);
  EXPECT_NEAR(first.vy, kPeriod / (kPeriod + p.tau_v) * cmd.vy, 1e-9);

  // Lines lost: the targets go to zero and the base stops through the filters.
  for (int i = 0; i < 20; ++i) cmd = follower.update(RackLinePair{}, BodyTwist{}, kPeriod);
  EXPECT_NEAR(cmd.vx, 0.0, 1e-6);
  EXPECT_NEAR(cmd.vy, 0.0, 1e-6);
  EXPECT_NEAR(cmd.omega, 0.0, 1e-6);
  EXPECT_EQ(follower.errors().status, AisleErrorStatus::kNoRackLines);
}

TEST(AisleFollower, CountsTheDistanceAlongTheAisleFromOdometry) {
  AisleFollower follower;
  follower.start(2.0);
  // The aisle lies 30 deg left of body x; the base moves along it at 0.2 m/s: 0.1732 forward, 0.1 left.
  const RackLinePair pair = pair_at(1.5, 1.5, 30.0 * kDeg);
  const BodyTwist odometry{0.2 * std::cos(30.0 * kDeg), 0.2 * std::sin(30.0 * kDeg), 0.0};
  follower.update(pair, BodyTwist{}, kPeriod);  // learns the heading
  for (int i = 0; i < 200; ++i) follower.update(pair, odometry, kPeriod);
  EXPECT_NEAR(follower.travelled(), 1.0, 1e-9);
  EXPECT_NEAR(follower.distance_to_go(), 1.0, 1e-9);
  EXPECT_THROW(AisleFollower(AisleFollowerParams{.reference_distance = 4.0}), std::invalid_argument);
}

TEST(AisleFollowing, TestI_LateralShiftOfOneMetre) {
  // [Table 7]: parallel to the racks, 1 m off d_ref, no travel along the aisle.
  const SeedAisleCase c = seed_aisle_case("I");
  const AisleRun r = run_aisle({c.setup}, c.duration, c.seed);
  const AisleFigures f = aisle_figures(r.traces[0]);
  print_figures(r.traces[0], f);
  EXPECT_LT(f.settle, 6.5);
  EXPECT_LT(std::abs(f.final_lateral), 0.02);
  EXPECT_LT(std::abs(f.final_heading), 0.5 * kDeg);
  EXPECT_LT(std::abs(f.final_along), 0.05);  // "the robot only moves in the lateral direction" [Fig. 4.48]
  EXPECT_LT(f.peak_lateral, 0.31);
  EXPECT_EQ(f.lost_fraction, 0.0);
}

TEST(AisleFollowing, TestII_ToTheReferenceWhileDrivingFiveMetres) {
  // [Table 8]: (-2.5, 1.5) -> (2.5, 1.0), parallel. The seed: lateral ~0.2 m/s for ~4 s, forward up to 0.3 m/s.
  const SeedAisleCase c = seed_aisle_case("II");
  const AisleRun r = run_aisle({c.setup}, c.duration, c.seed);
  const AisleFigures f = aisle_figures(r.traces[0]);
  print_figures(r.traces[0], f);
  EXPECT_LT(f.settle, 4.5);
  EXPECT_LT(f.peak_forward, 0.32);  // u0 = 0.3 m/s, plus the wheel slip
  EXPECT_GT(f.peak_lateral, 0.15);
  EXPECT_LT(f.peak_lateral, 0.31);
  EXPECT_LT(std::abs(f.final_lateral), 0.02);
  EXPECT_LT(std::abs(f.final_along), 0.10);  // odometry with 3 % wheel slip over 5 m
  EXPECT_EQ(f.lost_fraction, 0.0);
}

TEST(AisleFollowing, TestIII_TurnedTwentyFiveDegreesAtTheStart) {
  // [Table 9]: as II with 25 deg initial yaw; the seed: orientation and lateral converged in under 5 s. Both senses.
  for (const char* which : {"III +25", "III -25"}) {
    const SeedAisleCase c = seed_aisle_case(which);
    const std::string& name = c.setup.name;
    const AisleRun r = run_aisle({c.setup}, c.duration, c.seed);
    const AisleFigures f = aisle_figures(r.traces[0]);
    print_figures(r.traces[0], f);
    EXPECT_LT(f.settle, 5.0) << name;
    EXPECT_LT(f.heading_1deg, 3.0) << name;
    EXPECT_LT(std::abs(f.final_lateral), 0.02) << name;
    EXPECT_LT(std::abs(f.final_heading), 0.5 * kDeg) << name;
    EXPECT_LT(std::abs(f.final_along), 0.10) << name;
    EXPECT_EQ(f.lost_fraction, 0.0) << name;
  }
}

TEST(AisleFollowing, TwoPickersShareTheAisleOnePerSide) {
  // [section 4.3.3.1]: one picker 1 m off the right-hand face driving +x, one 1 m off the left-hand face driving -x;
  // they pass each other mid-aisle, each seeing the other in its scans.
  PickerSetup a = seed_aisle_setup("pair A (y=0 face, +x)", {-3.0, 1.3, 8.0 * kDeg}, 6.0);
  PickerSetup b = seed_aisle_setup("pair B (y=3 face, -x)", {3.0, 1.7, kPi - 8.0 * kDeg}, 6.0);
  b.follower.side = RackSide::kRight;  // travelling -x, the face y = 3 is on its right
  const AisleRun r = run_aisle({a, b}, 14.0, 404);
  for (const PickerTrace& t : r.traces) {
    const AisleFigures f = aisle_figures(t);
    print_figures(t, f);
    EXPECT_LT(f.settle, 5.0) << t.setup.name;
    EXPECT_EQ(f.lost_fraction, 0.0) << t.setup.name;
  }
  std::printf("[aisle follow] two pickers: closest approach of the bodies %.3f m\n", r.min_gap);
  // Each 1 m from its face in a 3 m aisle: 1 m between the centres, 0.5 m between the 0.5 m wide bodies.
  EXPECT_GT(r.min_gap, 0.45);
  const PickerTrace& ta = r.traces[0];
  const PickerTrace& tb = r.traces[1];
  EXPECT_GT(ta.pose.back().x, tb.pose.back().x + 2.0);  // they have passed each other
  // While passing (|dx| < 1 m) each keeps its own side.
  double worst = 0.0;
  for (std::size_t k = 0; k < ta.time.size(); ++k) {
    if (std::abs(ta.pose[k].x - tb.pose[k].x) < 1.0) {
      worst = std::max({worst, std::abs(lateral_error(ta, k)), std::abs(lateral_error(tb, k))});
    }
  }
  std::printf("[aisle follow] two pickers: worst distance from d_ref while passing %.3f m\n", worst);
  EXPECT_LT(worst, 0.03);
}

TEST(AisleFollowing, TheLeftFaceOptionMirrorsTestII) {
  PickerSetup s = seed_aisle_setup("II mirrored (left face)", {-2.5, 1.5, 0.0}, 5.0);
  s.follower.side = RackSide::kLeft;
  const AisleRun r = run_aisle({s}, 8.0, 505);
  const AisleFigures f = aisle_figures(r.traces[0]);
  print_figures(r.traces[0], f);
  EXPECT_NEAR(r.traces[0].lateral_ref, 2.0, 1e-12);
  EXPECT_LT(f.settle, 4.5);
  EXPECT_LT(std::abs(f.final_lateral), 0.02);
  EXPECT_GT(f.final_along, -4.0);  // under way along the aisle
}
