#include "perception/pallet_detector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/pose.hpp"
#include "pallet_scene.hpp"
#include "sim/depth_camera.hpp"

using fleet::geometry::Pose2;
using fleet::geometry::Vec2;
using fleet::perception::Detection;
using fleet::perception::PalletExpectation;
using fleet::test::PalletRow;
using namespace fleet;

namespace {

using ::fleet::geometry::kDeg;

// The truth the detector should report for a pallet: the face midpoint towards `camera_xy` and
// the yaw out of that face.
struct FaceTruth {
  Vec2 midpoint;
  double yaw;
};

FaceTruth face_truth(const Pose2& pallet, Vec2 camera_xy) {
  Vec2 dir{std::cos(pallet.yaw), std::sin(pallet.yaw)};
  if (geometry::dot(dir, camera_xy - pallet.position()) < 0.0) dir = -1.0 * dir;
  return {pallet.position() + 0.6 * dir, std::atan2(dir.y, dir.x)};
}

Vec2 camera_xy(const sim::DepthCamera& camera) {
  return {camera.model().mount.x, camera.model().mount.y};
}

PalletExpectation expect(const Pose2& pallet) {
  PalletExpectation e;
  e.pallet = pallet;
  e.base_height = PalletRow::kBase;
  return e;
}

}  // namespace

TEST(PalletDetector, FindsTheMidpointAndYawWithTheTofCameraPannedToTheSide) {
  sim::DepthCamera camera(sim::sick_3vistor_t(std::numbers::pi / 2), 11);
  // 1.5 m to the left of the camera, turned 3 deg; the robot (and the logistics position)
  // believe it square.
  const Pose2 nominal = perception::pallet_ahead_of_camera(camera.model(), 1.5, 0.0);
  Pose2 truth = nominal;
  truth.yaw += 3.0 * kDeg;
  const sim::DepthScene scene = PalletRow::around(truth);
  const FaceTruth want = face_truth(truth, camera_xy(camera));
  for (int frame = 0; frame < 5; ++frame) {
    const Detection d = perception::detect_pallet(camera.render(scene, Pose2{}), camera.model(), expect(nominal));
    ASSERT_TRUE(d.found) << d.reason;
    EXPECT_EQ(d.features, 6);
    EXPECT_LT(geometry::distance(d.midpoint, want.midpoint), 0.02);
    EXPECT_LT(std::abs(geometry::angle_diff(d.yaw, want.yaw)), 1.0 * kDeg);
  }
}

TEST(PalletDetector, FindsTheMidpointAndYawWithTheRealSenseAtTheRear) {
  sim::DepthCamera camera(sim::realsense_r200(), 12);
  const Pose2 nominal = perception::pallet_ahead_of_camera(camera.model(), 1.6, 0.0);
  Pose2 truth = nominal;
  truth.yaw -= 4.0 * kDeg;
  truth.y += 0.05;
  const sim::DepthScene scene = PalletRow::around(truth);
  const FaceTruth want = face_truth(truth, camera_xy(camera));
  for (int frame = 0; frame < 3; ++frame) {
    const Detection d = perception::detect_pallet(camera.render(scene, Pose2{}), camera.model(), expect(nominal));
    ASSERT_TRUE(d.found) << d.reason;
    EXPECT_LT(geometry::distance(d.midpoint, want.midpoint), 0.015);
    EXPECT_LT(std::abs(geometry::angle_diff(d.yaw, want.yaw)), 1.0 * kDeg);
    // The matched edges are the EPAL's: 100 / 227.5 / 145 / 227.5 / 100 mm.
    EXPECT_NEAR(d.edges[0], -0.400, 0.02);
    EXPECT_NEAR(d.edges[2], -0.0725, 0.02);
    EXPECT_NEAR(d.edges[3], 0.0725, 0.02);
    EXPECT_NEAR(d.edges[5], 0.400, 0.02);
  }
}

TEST(PalletDetector, CorrectsALogisticsPositionThatIsOffSideways) {
  // [Stacker thesis, section 7.2.3]: logistics misplaces the pallet by up to 0.5 m along the row.
  sim::DepthCamera camera(sim::sick_3vistor_t(std::numbers::pi / 2), 13);
  const Pose2 truth = perception::pallet_ahead_of_camera(camera.model(), 1.4, 0.0);
  Pose2 believed = truth;
  believed.x += 0.30;
  const sim::DepthScene scene = PalletRow::around(truth);
  const Detection d = perception::detect_pallet(camera.render(scene, Pose2{}), camera.model(), expect(believed));
  ASSERT_TRUE(d.found) << d.reason;
  EXPECT_LT(geometry::distance(d.midpoint, face_truth(truth, camera_xy(camera)).midpoint), 0.02);
}

TEST(PalletDetector, DiscardsAPalletOutsideTheExpectedDockingArea) {
  sim::DepthCamera camera(sim::sick_3vistor_t(std::numbers::pi / 2), 14);
  const Pose2 truth = perception::pallet_ahead_of_camera(camera.model(), 1.4, 0.0);
  Pose2 believed = truth;
  believed.x += 0.45;
  PalletExpectation e = expect(believed);
  e.area.lateral_half = 0.40;
  const sim::DepthScene scene = PalletRow::around(truth, /*neighbours=*/false);
  const Detection d = perception::detect_pallet(camera.render(scene, Pose2{}), camera.model(), e);
  EXPECT_FALSE(d.found);
  EXPECT_EQ(d.features, 6);
  EXPECT_NE(d.reason.find("outside the expected docking area"), std::string::npos) << d.reason;
  // With the area wide enough, the same frame is a detection.
  e.area.lateral_half = 0.50;
  EXPECT_TRUE(perception::detect_pallet(camera.render(scene, Pose2{}), camera.model(), e).found);
}

TEST(PalletDetector, NoPalletIsNotFoundAndSaysWhy) {
  sim::DepthCamera camera(sim::sick_3vistor_t(std::numbers::pi / 2), 15);
  const Pose2 nominal = perception::pallet_ahead_of_camera(camera.model(), 1.5, 0.0);
  // Only the limiter: nothing stands at pallet height above it.
  sim::DepthScene empty;
  empty.add_limiter({nominal.x, nominal.y, 0.0}, 20.0, 1.2, PalletRow::kBase);
  const Detection none = perception::detect_pallet(camera.render(empty, Pose2{}), camera.model(), expect(nominal));
  EXPECT_FALSE(none.found);
  EXPECT_NE(none.reason.find("no pallet face"), std::string::npos) << none.reason;
  // A closed crate of a pallet's size: a face, but no pockets.
  sim::DepthScene crate = empty;
  crate.add({nominal.x, nominal.y, nominal.yaw}, {sim::Box3{{-0.6, -0.4, 0.0}, {0.6, 0.4, 0.144}}}, PalletRow::kBase);
  const Detection closed = perception::detect_pallet(camera.render(crate, Pose2{}), camera.model(), expect(nominal));
  EXPECT_FALSE(closed.found);
  EXPECT_EQ(closed.reason, "no pallet-like transitions in the region of interest");
}

TEST(PalletDetector, ReportsHowManyFeaturesMatchedWhenAPocketIsBlocked) {
  sim::DepthCamera camera(sim::realsense_r200(), 16);
  const Pose2 nominal = perception::pallet_ahead_of_camera(camera.model(), 1.5, 0.0);
  sim::DepthScene scene = PalletRow::around(nominal, false);
  // A box stuffed into the right-hand pocket (seen from the camera) closes it.
  scene.add(nominal, {sim::Box3{{0.5, 0.08, 0.0}, {0.6, 0.29, 0.10}}}, PalletRow::kBase);
  const Detection d = perception::detect_pallet(camera.render(scene, Pose2{}), camera.model(), expect(nominal));
  EXPECT_FALSE(d.found);
  EXPECT_GE(d.features, 2);
  EXPECT_LT(d.features, 6);
  EXPECT_EQ(d.reason, "only " + std::to_string(d.features) + " of 6 features matched");
}

TEST(PalletTracker, FollowsThePalletWhileTheRobotDrivesAlongTheRow) {
  sim::DepthCamera camera(sim::sick_3vistor_t(std::numbers::pi / 2), 17);
  // The pallet 1.6 m to the left of the row the robot drives along +x; logistics puts it 0.25 m off.
  const Pose2 truth{3.0, 1.6 + 0.6, -std::numbers::pi / 2};
  const sim::DepthScene scene = PalletRow::around(truth);
  perception::PalletTracker tracker(camera.model());
  tracker.set_target({truth.x - 0.25, truth.y, truth.yaw}, PalletRow::kBase);
  int found = 0;
  for (double x = 2.0; x <= 2.6; x += 0.1) {
    const Pose2 robot{x, 0.0, 0.0};
    const Detection d = tracker.update(camera.render(scene, robot), robot);
    if (!d.found) continue;
    ++found;
    const Pose2 seen = geometry::body_pose_to_map(robot, d.pallet_pose());
    EXPECT_LT(geometry::distance(seen.position(), truth.position()), 0.03) << x;
  }
  EXPECT_GE(found, 6);
  ASSERT_TRUE(tracker.tracking());
  EXPECT_LT(geometry::distance(tracker.last_in_map()->position(), truth.position()), 0.03);
}

TEST(PalletDetector, ReadsOnlyItsWindowSoACameraNeedRenderNothingElse) {
  // Two cameras alike: a pixel's noise depends on the seed, the frame and the pixel, not on which
  // other pixels were rendered.
  sim::DepthCamera camera(sim::realsense_r200(), 15);
  sim::DepthCamera twin(sim::realsense_r200(), 15);
  const Pose2 truth = perception::pallet_ahead_of_camera(camera.model(), 1.6, 0.0);
  const sim::DepthScene scene = PalletRow::around(truth);
  const PalletExpectation e = expect(truth);
  const perception::PixelWindow window = perception::detection_window(camera.model(), e);
  ASSERT_FALSE(window.empty());
  EXPECT_LT((window.col1 - window.col0) * (window.row1 - window.row0), 640 * 480 / 2);

  const perception::DepthImage full = camera.render(scene, Pose2{});
  const perception::DepthImage part = twin.render(scene, Pose2{}, window);
  int inside = 0;
  for (int row = 0; row < part.height; ++row) {
    for (int col = 0; col < part.width; ++col) {
      if (!window.contains(col, row)) {
        ASSERT_FALSE(part.has_return(col, row)) << col << "," << row;
        continue;
      }
      ++inside;
      ASSERT_EQ(full.has_return(col, row), part.has_return(col, row)) << col << "," << row;
      if (full.has_return(col, row)) {
        ASSERT_EQ(full.at(col, row), part.at(col, row));
      }
    }
  }
  EXPECT_GT(inside, 0);
  const Detection from_full = perception::detect_pallet(full, camera.model(), e);
  const Detection from_part = perception::detect_pallet(part, camera.model(), e);
  ASSERT_TRUE(from_part.found) << from_part.reason;
  EXPECT_EQ(from_full.midpoint.x, from_part.midpoint.x);
  EXPECT_EQ(from_full.midpoint.y, from_part.midpoint.y);
  EXPECT_EQ(from_full.yaw, from_part.yaw);
}
