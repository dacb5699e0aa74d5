#include "aisle/aisle_follower.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "aisle/hough_lines.hpp"
#include "aisle/rack_aisle_sim.hpp"
#include "geometry/polygon.hpp"
#include "sim/forklift_body.hpp"

using namespace fleet::aisle;
using fleet::geometry::Polygon;
using fleet::geometry::Pose2;
using fleet::sim::BodyTwist;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
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

// ---- closed loop: the simulated mecanum body, the two simulated lidars, the detector and the follower ------------

struct PickerSetup {
  std::string name;
  Pose2 start;
  AisleFollowerParams follower;
  double distance = 0.0;  ///< X_f − X_i along the picker's own direction of travel
};

struct PickerTrace {
  PickerSetup setup;
  double travel_yaw = 0.0;   ///< the aisle direction the picker travels along (0 or pi)
  double lateral_ref = 0.0;  ///< aisle-frame y of d_ref from the chosen face
  std::vector<double> time;
  std::vector<Pose2> pose;
  std::vector<BodyTwist> twist;  ///< the true body twist
  std::vector<bool> lines_found;
};

struct RunResult {
  std::vector<PickerTrace> traces;
  double min_gap = std::numeric_limits<double>::infinity();  ///< closest approach of two pickers' bodies
};

RunResult run_aisle(const std::vector<PickerSetup>& setups, double duration, std::uint64_t seed) {
  const RackAisle aisle;
  std::vector<fleet::sim::ForkliftBody> bodies;
  // The plant the thesis designed and ran the aisle laws on: first order, τ = 0.02 s [Picker thesis, eq. 4.29]. The
  // Summit-XLS default follows the measured step of Fig. 4.27 (τ = 0.075 s), on which Test III settles in ~12 s.
  fleet::sim::ForkliftParams body_params = fleet::sim::summit_xls_body_params();
  body_params.wheel_time_constant = 0.02;
  std::vector<PickerLidars> lidars;
  std::vector<RackLineDetector> detectors;
  std::vector<AisleFollower> followers;
  RunResult result;
  for (std::size_t i = 0; i < setups.size(); ++i) {
    const PickerSetup& s = setups[i];
    bodies.emplace_back(body_params, s.start, std::mt19937_64(seed + 17 * i));
    lidars.emplace_back(picker_lidar_mounts(), 0.02, std::mt19937_64(seed + 17 * i + 1));
    detectors.emplace_back();
    followers.emplace_back(s.follower);
    followers.back().start(s.distance);
    PickerTrace trace;
    trace.setup = s;
    trace.travel_yaw = std::abs(s.start.yaw) < kPi / 2.0 ? 0.0 : kPi;
    const bool right_face_low = (trace.travel_yaw == 0.0) == (s.follower.side == RackSide::kRight);
    trace.lateral_ref =
        right_face_low ? s.follower.reference_distance : aisle.params().width - s.follower.reference_distance;
    result.traces.push_back(trace);
  }
  const int steps = static_cast<int>(std::lround(duration / kPeriod));
  for (int k = 0; k < steps; ++k) {
    std::vector<BodyTwist> commands(bodies.size());
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      std::vector<Polygon> others;  // the other pickers are obstacles to this one's lidars
      for (std::size_t j = 0; j < bodies.size(); ++j) {
        if (j != i) others.push_back(bodies[j].footprint_polygon());
      }
      const auto scans = lidars[i].scan(bodies[i].pose(), aisle, others);
      const RackLinePair pair = detectors[i].detect(scans, lidars[i].mounts());
      // The encoders: what the wheels turn at, through the forward kinematics (slip makes it differ from the truth).
      const BodyTwist odometry = bodies[i].kinematics().forward(bodies[i].wheel_speeds());
      commands[i] = followers[i].update(pair, odometry, kPeriod);
      result.traces[i].lines_found.push_back(pair.found());
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      bodies[i].step(commands[i], kPeriod);
      PickerTrace& t = result.traces[i];
      t.time.push_back((k + 1) * kPeriod);
      t.pose.push_back(bodies[i].pose());
      t.twist.push_back(bodies[i].twist());
    }
    for (std::size_t i = 0; i < bodies.size(); ++i) {
      for (std::size_t j = i + 1; j < bodies.size(); ++j) {
        result.min_gap = std::min(result.min_gap, fleet::geometry::convex_polygons_distance(
                                                      bodies[i].footprint_polygon(), bodies[j].footprint_polygon()));
      }
    }
  }
  return result;
}

double lateral_error(const PickerTrace& t, std::size_t k) {
  return t.pose[k].y - t.lateral_ref;
}
double heading_error(const PickerTrace& t, std::size_t k) {
  return fleet::geometry::angle_diff(t.pose[k].yaw, t.travel_yaw);
}
double along(const PickerTrace& t, std::size_t k) {
  const double dx = t.pose[k].x - t.setup.start.x;
  return t.travel_yaw == 0.0 ? dx : -dx;
}

/// From when on the picker stays within `lateral_tol` of d_ref and `heading_tol` of the aisle, seconds from the
/// start; infinity when it is still outside at the end.
double settle_time(const PickerTrace& t, double lateral_tol, double heading_tol) {
  for (std::size_t k = t.time.size(); k-- > 0;) {
    if (std::abs(lateral_error(t, k)) > lateral_tol || std::abs(heading_error(t, k)) > heading_tol) {
      return k + 1 == t.time.size() ? std::numeric_limits<double>::infinity() : t.time[k];
    }
  }
  return 0.0;
}

struct Figures {
  double settle = 0.0;         ///< within 3 cm of d_ref and 1 deg of the aisle, for good
  double lateral_5cm = 0.0;    ///< first time within 5 cm of d_ref
  double heading_1deg = 0.0;   ///< first time within 1 deg of the aisle
  double peak_lateral = 0.0;   ///< m/s
  double peak_forward = 0.0;   ///< m/s
  double peak_yaw_rate = 0.0;  ///< rad/s
  double final_lateral = 0.0;  ///< m
  double final_heading = 0.0;  ///< rad
  double final_along = 0.0;    ///< travelled minus requested, m
  double lost_fraction = 0.0;  ///< frames without a line pair
};

Figures figures(const PickerTrace& t) {
  Figures f;
  f.settle = settle_time(t, 0.03, 1.0 * kDeg);
  f.lateral_5cm = f.heading_1deg = std::numeric_limits<double>::infinity();
  int lost = 0;
  for (std::size_t k = 0; k < t.time.size(); ++k) {
    if (std::abs(lateral_error(t, k)) <= 0.05) f.lateral_5cm = std::min(f.lateral_5cm, t.time[k]);
    if (std::abs(heading_error(t, k)) <= 1.0 * kDeg) f.heading_1deg = std::min(f.heading_1deg, t.time[k]);
    f.peak_lateral = std::max(f.peak_lateral, std::abs(t.twist[k].vy));
    f.peak_forward = std::max(f.peak_forward, std::abs(t.twist[k].vx));
    f.peak_yaw_rate = std::max(f.peak_yaw_rate, std::abs(t.twist[k].omega));
    if (!t.lines_found[k]) ++lost;
  }
  const std::size_t last = t.time.size() - 1;
  f.final_lateral = lateral_error(t, last);
  f.final_heading = heading_error(t, last);
  f.final_along = along(t, last) - t.setup.distance;
  f.lost_fraction = static_cast<double>(lost) / static_cast<double>(t.time.size());
  return f;
}

void print_figures(const PickerTrace& t, const Figures& f) {
  std::printf(
      "[aisle follow] %-28s settled (3 cm, 1 deg) %.2f s | lateral <5 cm %.2f s | heading <1 deg %.2f s | peak v %.3f "
      "u %.3f m/s r %.3f rad/s | final lateral %+.3f m heading %+.2f deg along %+.3f m | frames without pair %.1f %%\n",
      t.setup.name.c_str(), f.settle, f.lateral_5cm, f.heading_1deg, f.peak_lateral, f.peak_forward, f.peak_yaw_rate,
      f.final_lateral, f.final_heading / kDeg, f.final_along, 100.0 * f.lost_fraction);
}

/// The seed's tests I-III [Picker thesis, Tables 7-9]: rack 3 m, d_ref = 1 m from the right-hand face (y = 0).
PickerSetup seed_test(const std::string& name, Pose2 start, double distance) {
  PickerSetup s;
  s.name = name;
  s.start = start;
  s.distance = distance;
  return s;
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
  const RunResult r = run_aisle({seed_test("I (1 m lateral shift)", {0.0, 2.0, 0.0}, 0.0)}, 8.0, 101);
  const Figures f = figures(r.traces[0]);
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
  const RunResult r = run_aisle({seed_test("II (-2.5,1.5)->(2.5,1.0)", {-2.5, 1.5, 0.0}, 5.0)}, 22.0, 202);
  const Figures f = figures(r.traces[0]);
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
  for (double yaw : {25.0, -25.0}) {
    const std::string name = yaw > 0 ? "III (+25 deg)" : "III (-25 deg)";
    const RunResult r = run_aisle({seed_test(name, {-2.5, 1.5, yaw * kDeg}, 5.0)}, 22.0, 303);
    const Figures f = figures(r.traces[0]);
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
  PickerSetup a = seed_test("pair A (y=0 face, +x)", {-3.0, 1.3, 8.0 * kDeg}, 6.0);
  PickerSetup b = seed_test("pair B (y=3 face, -x)", {3.0, 1.7, kPi - 8.0 * kDeg}, 6.0);
  b.follower.side = RackSide::kRight;  // travelling -x, the face y = 3 is on its right
  const RunResult r = run_aisle({a, b}, 14.0, 404);
  for (const PickerTrace& t : r.traces) {
    const Figures f = figures(t);
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
  PickerSetup s = seed_test("II mirrored (left face)", {-2.5, 1.5, 0.0}, 5.0);
  s.follower.side = RackSide::kLeft;
  const RunResult r = run_aisle({s}, 8.0, 505);
  const Figures f = figures(r.traces[0]);
  print_figures(r.traces[0], f);
  EXPECT_NEAR(r.traces[0].lateral_ref, 2.0, 1e-12);
  EXPECT_LT(f.settle, 4.5);
  EXPECT_LT(std::abs(f.final_lateral), 0.02);
  EXPECT_GT(f.final_along, -4.0);  // under way along the aisle
}
