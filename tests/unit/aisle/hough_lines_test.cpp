#include "aisle/hough_lines.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "aisle/rack_aisle_sim.hpp"
#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"

using namespace fleet::aisle;
using fleet::geometry::Polygon;
using fleet::geometry::Pose2;
using fleet::geometry::Vec2;

namespace {

constexpr double kPi = std::numbers::pi;
using ::fleet::geometry::kDeg;

/// `n` points evenly along the segment a-b.
void add_segment(std::vector<Vec2>& points, Vec2 a, Vec2 b, int n) {
  for (int i = 0; i < n; ++i) points.push_back(a + (b - a) * (static_cast<double>(i) / (n - 1)));
}

/// A line through `p` with direction `heading`, as the Hough transform would report it.
HoughLine line_through(Vec2 p, double heading, int votes) {
  double theta = heading + kPi / 2.0;
  double rho = p.x * std::cos(theta) + p.y * std::sin(theta);
  if (theta >= kPi) {
    theta -= kPi;
    rho = -rho;
  }
  if (theta < 0.0) {
    theta += kPi;
    rho = -rho;
  }
  return {theta, rho, votes};
}

/// The base frame's view of an aisle frame: where the two faces are, seen from a base at `pose`.
struct TrueFaces {
  double heading;         ///< aisle direction in the base frame
  double right_distance;  ///< base centre to the face y = 0
  double left_distance;   ///< base centre to the face y = width
};

TrueFaces true_faces(const Pose2& pose, double width) {
  return {fleet::geometry::normalize_angle(-pose.yaw), pose.y, width - pose.y};
}

}  // namespace

TEST(PickerLidarMounts, SitOnOppositeCornersFacingOutwards) {
  const auto mounts = picker_lidar_mounts();
  EXPECT_DOUBLE_EQ(mounts[0].pose.x, 0.325);
  EXPECT_DOUBLE_EQ(mounts[0].pose.y, -0.25);
  EXPECT_DOUBLE_EQ(mounts[0].pose.yaw, -kPi / 4.0);
  EXPECT_DOUBLE_EQ(mounts[1].pose.x, -0.325);
  EXPECT_DOUBLE_EQ(mounts[1].pose.y, 0.25);
  EXPECT_DOUBLE_EQ(mounts[1].pose.yaw, 3.0 * kPi / 4.0);
  EXPECT_NEAR(mounts[0].field_of_view, 270.0 * kDeg, 1e-12);
}

TEST(VirtualRangeImage, PutsReturnsInTheBaseFrameAndDropsWhatTheSensorCannotSee) {
  const auto mounts = picker_lidar_mounts();
  fleet::planning::LidarScan scan;
  scan.angle_min = -kPi;
  scan.angle_increment = kPi / 2.0;  // beams at -180, -90, 0 and 90 degrees relative to the sensor
  scan.ranges = {1.0, 1.0, 1.0, std::numeric_limits<double>::infinity()};
  fleet::planning::LidarScan empty = scan;
  empty.ranges.assign(4, std::numeric_limits<double>::infinity());
  const std::vector<fleet::planning::LidarScan> scans{scan, empty};
  const std::vector<Vec2> points = virtual_range_image(scans, mounts, RangeImageExtent{});
  // -180 deg lies in the blind wedge; -90 and 0 deg remain.
  ASSERT_EQ(points.size(), 2u);
  const double h = std::sqrt(0.5);
  EXPECT_NEAR(points[0].x, 0.325 - h, 1e-9);  // -90 deg from a sensor facing -45 deg: towards -135 deg
  EXPECT_NEAR(points[0].y, -0.25 - h, 1e-9);
  EXPECT_NEAR(points[1].x, 0.325 + h, 1e-9);  // straight out of the sensor: towards -45 deg
  EXPECT_NEAR(points[1].y, -0.25 - h, 1e-9);

  RangeImageExtent small;
  small.half_width = 0.5;
  EXPECT_TRUE(virtual_range_image(scans, mounts, small).empty());
  EXPECT_THROW(virtual_range_image(std::vector<fleet::planning::LidarScan>{scan}, mounts, small),
               std::invalid_argument);
}

TEST(HoughAccumulator, PeaksSitOnTheLinesThePointsLieOn) {
  std::vector<Vec2> points;
  add_segment(points, {-3.0, 1.2}, {3.0, 1.2}, 200);  // left face, parallel
  add_segment(points, {-3.0, -1.8 - 3.0 * std::tan(5 * kDeg)}, {3.0, -1.8 + 3.0 * std::tan(5 * kDeg)}, 200);
  HoughParams params;
  HoughAccumulator acc(params, std::hypot(4.0, 4.0));
  EXPECT_EQ(acc.theta_bins(), 180);
  acc.vote(points);
  const std::vector<HoughLine> peaks = acc.peaks();
  ASSERT_GE(peaks.size(), 2u);
  // The two strongest peaks are the two segments.
  const HoughLine& a = peaks[0].lateral_offset() > 0 ? peaks[0] : peaks[1];
  const HoughLine& b = peaks[0].lateral_offset() > 0 ? peaks[1] : peaks[0];
  EXPECT_NEAR(a.direction(), 0.0, 0.5 * kDeg + 1e-9);
  EXPECT_NEAR(a.lateral_offset(), 1.2, 0.03);
  EXPECT_NEAR(b.direction(), 5.0 * kDeg, 0.5 * kDeg + 1e-9);
  EXPECT_NEAR(b.lateral_offset(), -1.8, 0.03);
  EXPECT_GE(a.votes, 150);
}

TEST(HoughAccumulator, AHigherVoteLimitLosesSparseLines) {
  // [Picker thesis, Fig. 4.44]: with sparse data a limit of 40 finds nothing where 20 still finds the line.
  std::vector<Vec2> points;
  add_segment(points, {-2.0, 1.5}, {2.0, 1.5}, 30);
  HoughParams params;
  params.vote_limit = 20;
  HoughAccumulator low(params, 6.0);
  low.vote(points);
  EXPECT_FALSE(low.peaks().empty());
  params.vote_limit = 40;
  HoughAccumulator high(params, 6.0);
  high.vote(points);
  EXPECT_TRUE(high.peaks().empty());
}

TEST(HoughAccumulator, IgnoresLinesBeyondTheHeadingLimit) {
  std::vector<Vec2> points;
  add_segment(points, {1.0, -3.0}, {1.0, 3.0}, 200);  // across the base: 90 deg from body x
  HoughAccumulator acc(HoughParams{}, 6.0);
  acc.vote(points);
  EXPECT_TRUE(acc.peaks().empty());
}

TEST(SelectRackPair, TakesTheParallelPairWithTheFewestPointsBetween) {
  // [Picker thesis, Fig. 4.40]: Line_3 between the faces encloses more returns than the true face Line_1.
  std::vector<Vec2> points;
  add_segment(points, {-3.0, 1.5}, {3.0, 1.5}, 300);    // Line_1, the left face
  add_segment(points, {-3.0, -1.5}, {3.0, -1.5}, 300);  // Line_2, the right face
  add_segment(points, {-3.0, 1.65}, {3.0, 1.65}, 250);  // Line_3, returns from inside the pallets behind it
  add_segment(points, {-0.5, 0.3}, {0.5, 0.3}, 40);     // clutter between the faces
  const std::vector<HoughLine> lines{line_through({0, 1.5}, 0, 300), line_through({0, -1.5}, 0, 300),
                                     line_through({0, 1.65}, 0, 250)};
  const RackLinePair pair = select_rack_pair(lines, points, RackLineParams{});
  ASSERT_TRUE(pair.found()) << to_string(pair.status);
  EXPECT_NEAR(pair.left.lateral_offset(), 1.5, 1e-9);
  EXPECT_NEAR(pair.right.lateral_offset(), -1.5, 1e-9);
  EXPECT_NEAR(pair.width, 3.0, 1e-9);
  EXPECT_EQ(pair.points_between, 40);
}

TEST(SelectRackPair, SaysWhyThereIsNoPair) {
  const std::vector<Vec2> none;
  const RackLineParams params;
  EXPECT_EQ(select_rack_pair(std::vector<HoughLine>{}, none, params).status, PairStatus::kNoLines);
  EXPECT_EQ(select_rack_pair(std::vector<HoughLine>{line_through({0, -1}, 0, 100)}, none, params).status,
            PairStatus::kNoLineLeft);
  EXPECT_EQ(select_rack_pair(std::vector<HoughLine>{line_through({0, 1}, 0, 100)}, none, params).status,
            PairStatus::kNoLineRight);
  // A 4 m aisle is outside 3 m ± 10 %.
  EXPECT_EQ(select_rack_pair(std::vector<HoughLine>{line_through({0, 2}, 0, 100), line_through({0, -2}, 0, 100)}, none,
                             params)
                .status,
            PairStatus::kNoPairInWidth);
  // 3 m apart at the base but 8 deg apart in direction.
  EXPECT_EQ(select_rack_pair(
                std::vector<HoughLine>{line_through({0, 1.5}, 4 * kDeg, 100), line_through({0, -1.5}, -4 * kDeg, 100)},
                none, params)
                .status,
            PairStatus::kNotParallel);
  EXPECT_EQ(to_string(PairStatus::kNotParallel), "no parallel pair");
}

TEST(SelectRackPair, MeasuresTheWidthAcrossTheLinesNotAlongTheBody) {
  // Turned 25 deg to the aisle (test III), the faces are 3.31 m apart along body y: 3.0 m across the lines.
  const double heading = -25.0 * kDeg;
  const std::vector<HoughLine> lines{line_through({0, 1.5 / std::cos(heading)}, heading, 100),
                                     line_through({0, -1.5 / std::cos(heading)}, heading, 100)};
  const RackLinePair pair = select_rack_pair(lines, std::vector<Vec2>{}, RackLineParams{});
  ASSERT_TRUE(pair.found()) << to_string(pair.status);
  EXPECT_NEAR(pair.width, 3.0, 1e-9);
  EXPECT_NEAR(pair.heading, heading, 1e-9);
}

TEST(RefitLine, RecoversASubCellLineFromNoisyPoints) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  const double heading = 0.37 * kDeg;
  std::vector<Vec2> points;
  for (int i = 0; i < 400; ++i) {
    const double x = -3.0 + 6.0 * i / 399.0;
    points.push_back({x, 1.234 + x * std::tan(heading) + noise(rng)});
  }
  const HoughLine rough = line_through({0, 1.25}, 0.0, 400);
  const HoughLine fine = refit_line(refit_line(rough, points, 0.08), points, 0.08);
  EXPECT_NEAR(fine.direction(), heading, 0.05 * kDeg);
  EXPECT_NEAR(fine.lateral_offset(), 1.234, 0.005);
  EXPECT_EQ(fine.votes, 400);
}

namespace {

struct AisleScanStats {
  int frames = 0;
  int found = 0;
  double worst_width = 0.0;
  double worst_heading = 0.0;
  double worst_side = 0.0;
  double mean_side = 0.0;  ///< mean signed error of the face distances (positive: faces seen too far)
  Pose2 worst_pose;
};

/// Scans the simulated aisle from a grid of poses and compares the pair with the truth.
AisleScanStats scan_aisle_grid(const RackLineParams& params, double range_sigma, bool with_other_picker) {
  const RackAisle aisle;
  std::vector<Polygon> others;
  if (with_other_picker) others.push_back(fleet::geometry::footprint_polygon({0.6, 2.0, 0.0}, {0.65, 0.50}));
  PickerLidars lidars(picker_lidar_mounts(), range_sigma, std::mt19937_64(11));
  RackLineDetector detector(params);
  AisleScanStats stats;
  // Off the 5 cm ρ cells and at every phase of the uprights (every 3.5 m) and pallets.
  for (double x : {-1.73, -0.91, 0.02, 0.37, 1.19}) {
    for (double y : with_other_picker ? std::vector<double>{0.72, 0.96, 1.04, 1.19}
                                      : std::vector<double>{0.72, 1.04, 1.51, 2.27}) {
      for (double yaw_deg : {-30.0, -12.3, 0.4, 7.1, 25.0}) {
        const Pose2 pose{x, y, yaw_deg * kDeg};
        const auto scans = lidars.scan(pose, aisle, others);
        const RackLinePair pair = detector.detect(scans, lidars.mounts());
        ++stats.frames;
        if (!pair.found()) {
          ADD_FAILURE() << "no pair at (" << x << ", " << y << ", " << yaw_deg << " deg): " << to_string(pair.status);
          continue;
        }
        ++stats.found;
        const TrueFaces truth = true_faces(pose, aisle.params().width);
        const double width = std::abs(pair.width - aisle.params().width);
        const double heading = std::abs(pair.heading - truth.heading);
        const double side = std::max(std::abs(std::abs(pair.right.rho) - truth.right_distance),
                                     std::abs(std::abs(pair.left.rho) - truth.left_distance));
        if (width > stats.worst_width || heading > stats.worst_heading || side > stats.worst_side) {
          stats.worst_pose = pose;
        }
        stats.worst_width = std::max(stats.worst_width, width);
        stats.worst_heading = std::max(stats.worst_heading, heading);
        stats.worst_side = std::max(stats.worst_side, side);
        stats.mean_side +=
            (std::abs(pair.right.rho) - truth.right_distance) + (std::abs(pair.left.rho) - truth.left_distance);
      }
    }
  }
  stats.mean_side /= 2.0 * stats.found;
  return stats;
}

void print_stats(const char* label, const AisleScanStats& s) {
  std::printf(
      "[aisle lines] %-34s found %d/%d  worst |width err| %.3f m  |heading err| %.2f deg  |face dist err| %.3f m  mean "
      "face dist err %+.3f m (last worst at %.2f, %.2f, %.1f deg)\n",
      label, s.found, s.frames, s.worst_width, s.worst_heading / kDeg, s.worst_side, s.mean_side, s.worst_pose.x,
      s.worst_pose.y, s.worst_pose.yaw / kDeg);
}

}  // namespace

TEST(RackLineDetector, FindsBothFacesOfTheSimulatedAisle) {
  // A 3.0 m aisle, uprights every 3.5 m, hollow pallets and empty slots, ±40 mm lidar noise (σ = 20 mm), from
  // 0.7 m to 2.3 m off the right face and -30 to +25 deg to the aisle: both faces, refined.
  const AisleScanStats s = scan_aisle_grid(RackLineParams{}, 0.02, false);
  print_stats("refined, sigma 20 mm, limit 40", s);
  EXPECT_EQ(s.found, s.frames);
  EXPECT_LT(s.worst_width, 0.03);
  EXPECT_LT(s.worst_heading, 0.4 * kDeg);
  EXPECT_LT(s.worst_side, 0.025);
}

TEST(RackLineDetector, HoughPeaksAloneAreWithinTheirCells) {
  // The seed's lines as they are, at both of its vote limits: heading within the 1 deg step, width within 2 cells.
  for (int limit : {20, 40}) {
    RackLineParams params;
    params.hough.vote_limit = limit;
    params.pair.refine = false;
    const AisleScanStats s = scan_aisle_grid(params, 0.02, false);
    print_stats(limit == 20 ? "Hough peaks, sigma 20 mm, limit 20" : "Hough peaks, sigma 20 mm, limit 40", s);
    EXPECT_EQ(s.found, s.frames);
    EXPECT_LT(s.worst_width, 0.10);
    EXPECT_LT(s.worst_heading, 1.0 * kDeg);
    EXPECT_LT(s.worst_side, 0.06);
  }
}

TEST(RackLineDetector, CopesWithTheFullDataSheetNoiseAndAnotherPickerInTheAisle) {
  // σ = 40 mm (the data sheet's ±40 mm as 1σ) and the other picker of the aisle 1 m off the far face.
  const AisleScanStats s = scan_aisle_grid(RackLineParams{}, 0.04, true);
  print_stats("refined, sigma 40 mm, other picker", s);
  EXPECT_EQ(s.found, s.frames);
  EXPECT_LT(s.worst_width, 0.06);
  EXPECT_LT(s.worst_heading, 0.6 * kDeg);
  EXPECT_LT(s.worst_side, 0.04);
}

TEST(RackLineDetector, ReportsAnOpenSideAndAWrongWidth) {
  PickerLidars lidars(picker_lidar_mounts(), 0.02, std::mt19937_64(3));
  RackLineDetector detector;
  // Beyond the end of the racks only the right-hand one goes on: an open left side. Emulated by an aisle so wide
  // that its left face is out of the range image.
  RackAisleParams wide;
  wide.width = 9.0;
  const auto open = detector.detect(lidars.scan({0.0, 1.0, 0.0}, RackAisle(wide)), lidars.mounts());
  EXPECT_EQ(open.status, PairStatus::kNoLineLeft) << to_string(open.status);

  RackAisleParams four;
  four.width = 4.0;  // beyond 3 m + 10 %
  const auto off = detector.detect(lidars.scan({0.0, 2.0, 0.0}, RackAisle(four)), lidars.mounts());
  EXPECT_EQ(off.status, PairStatus::kNoPairInWidth) << to_string(off.status);

  EXPECT_EQ(detector.detect(std::vector<Vec2>{{1.0, 1.0}}).status, PairStatus::kTooFewPoints);
}

TEST(RackAisle, CastsTheSameRangesAsTheSharedLidarSimulation) {
  // The aisle's own ray casting against planning::LidarSim over the aisle's polygons, noise off.
  const RackAisle aisle;
  const std::vector<Polygon> polygons = aisle.polygons();
  const fleet::planning::LidarSim reference({1440, 10.0, 0.0});
  for (const Pose2& sensor : {Pose2{0.3, 0.4, -0.7}, Pose2{-2.1, 2.6, 2.4}, Pose2{1.75, 1.5, 0.1}}) {
    const fleet::planning::LidarScan expected = reference.scan(sensor, polygons);
    int hits = 0;
    for (std::size_t i = 0; i < expected.ranges.size(); ++i) {
      const double a = sensor.yaw + expected.angle_min + static_cast<double>(i) * expected.angle_increment;
      const double r = aisle.cast(sensor.position(), {std::cos(a), std::sin(a)}, 10.0);
      if (std::isfinite(expected.ranges[i])) {
        ++hits;
        ASSERT_NEAR(r, expected.ranges[i], 1e-9) << "beam " << i;
      } else {
        ASSERT_FALSE(std::isfinite(r)) << "beam " << i;
      }
    }
    EXPECT_GT(hits, 1000);
  }
}
