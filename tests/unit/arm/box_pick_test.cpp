// Locating boxes by their markers with the depth camera on the boom and picking them with the arm
// [Picker thesis, sections 3.1.1, 4.4]: what the picker does parked beside a pallet.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <vector>

#include "arm/pick_motion.hpp"
#include "perception/box_marker_camera.hpp"

namespace fleet {
namespace {

using arm::Box;
using perception::BoxMarker;
using perception::BoxSighting;
using perception::DepthMarkerCamera;
using perception::DepthMarkerCameraParams;

const Box kBox{3.0, 0.30, 0.30, 0.25};
constexpr double kPalletTop = 0.144;  // EPAL

/// The picker parked side-on at the origin heading +x, a pallet on its left 0.15 m from its side, and one row of
/// three boxes along the pallet's near edge, each marked on its top face.
std::vector<BoxMarker> boxes_beside() {
  std::vector<BoxMarker> boxes;
  const double top = kPalletTop + kBox.height;
  const double row_y = 0.25 + 0.15 + 0.5 * kBox.width;
  const double yaws[] = {0.0, 0.3, -0.2};
  for (int k = 0; k < 3; ++k) boxes.push_back({k + 1, {-0.35 + 0.35 * k, row_y, top}, yaws[k]});
  return boxes;
}

DepthMarkerCameraParams left_boom() {
  DepthMarkerCameraParams p;
  p.mount = {0.25, 0.20, 1.50};
  return p;
}

TEST(BoxPick, TheBoomCameraLocatesEveryBoxAndTheArmGripsItWhereItIs) {
  const std::vector<BoxMarker> boxes = boxes_beside();
  DepthMarkerCamera camera(left_boom(), 3);
  camera.look_at({0.0, 0.7, kPalletTop});
  std::map<int, BoxSighting> first;
  for (double t = 0.0; t < 1.0 && first.size() < boxes.size(); t += 1.0 / 30.0) {
    if (!camera.frame_due(t)) continue;
    for (const BoxSighting& s : camera.capture(t, {}, boxes)) first.emplace(s.id, s);
  }
  ASSERT_EQ(first.size(), boxes.size()) << "every box read within a second";

  const arm::PickMotionPlanner planner(arm::Ur5{}, arm::VacuumGripper{});
  for (const BoxMarker& truth : boxes) {
    const BoxSighting& seen = first.at(truth.id);
    const arm::MotionPlan plan = planner.plan_pick({kBox, seen.top_centre, seen.yaw});
    ASSERT_TRUE(plan.ok) << "box " << truth.id << ": " << plan.reason;
    // Where the plate lands on the true face: the location error in the face's axes.
    const Eigen::Vector3d error = seen.top_centre - truth.top_centre;
    const double c = std::cos(truth.yaw);
    const double s = std::sin(truth.yaw);
    const double along_length = c * error.x() + s * error.y();
    const double along_width = -s * error.x() + c * error.y();
    const double plate_on_face = plan.plate_yaw_on_box + geometry::angle_diff(seen.yaw, truth.yaw);
    EXPECT_TRUE(planner.gripper().covers(kBox, plate_on_face, along_length, along_width))
        << "box " << truth.id << " located " << error.norm() * 1000.0 << " mm off";
    EXPECT_LT(error.norm(), 0.02) << "box " << truth.id;
    std::printf("box %d at %.2f m: located %.1f mm off, %.2f deg; pick %.1f s\n", truth.id, seen.distance,
                error.norm() * 1000.0, geometry::angle_diff(seen.yaw, truth.yaw) * 180.0 / std::numbers::pi,
                plan.duration());
  }
}

TEST(BoxPick, TheReadingRangeShrinksWithSpeedAndTheFaceMustLookAtTheCamera) {
  // Experiment 1 [Picker thesis, section 4.2.9.2.1]: to 6.5 m at 0.3 m/s, about 3 m at 1.0 m/s.
  const DepthMarkerCameraParams defaults;
  EXPECT_NEAR(defaults.read_range(0.0), 6.5, 1e-12);
  EXPECT_NEAR(defaults.read_range(0.3), 6.5, 1e-12);
  EXPECT_NEAR(defaults.read_range(1.0), 3.0, 1e-12);
  EXPECT_NEAR(defaults.read_range(3.0), defaults.range_min, 1e-12);

  DepthMarkerCameraParams quick = left_boom();
  quick.read_range_fast = 1.0;  // a camera that reads only to 1 m at 1.0 m/s
  DepthMarkerCamera camera(quick, 1);
  const BoxMarker box = boxes_beside().front();
  camera.look_at(box.top_centre);
  BoxSighting s;
  ASSERT_TRUE(camera.ideal({}, box, 0.3, s));
  EXPECT_NEAR(s.distance, (box.top_centre - quick.mount).norm(), 1e-12);
  EXPECT_FALSE(camera.ideal({}, box, 1.0, s)) << s.distance << " m is beyond the range at 1.0 m/s";

  // A box top far away is seen too flat to read: 4.4 m out and 1 m down is 77° off its normal.
  const BoxMarker far{9, {4.5, 0.2, 0.5}, 0.0};
  camera.look_at(far.top_centre);
  EXPECT_FALSE(camera.ideal({}, far, 0.0, s));
  camera.look_at({-2.0, 0.0, 0.5});  // turned away
  EXPECT_FALSE(camera.ideal({}, box, 0.3, s));
  const BoxMarker above{10, {1.5, 0.20, 1.9}, 0.0};  // its face above the camera: seen from underneath
  camera.look_at(above.top_centre);
  EXPECT_FALSE(camera.ideal({}, above, 0.3, s));
}

}  // namespace
}  // namespace fleet
