#include "perception/detection_sweep.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "geometry/pose.hpp"
#include "pallet_scene.hpp"
#include "sim/depth_camera.hpp"

using namespace fleet;
using perception::SweepAxis;
using perception::SweepResult;

namespace {

using ::fleet::geometry::kDeg;

perception::SweepSetup setup_for(sim::DepthCamera& camera) {
  perception::SweepSetup setup;
  setup.camera = camera.model();
  setup.render = test::row_renderer(camera);
  setup.base_height = test::PalletRow::kBase;
  return setup;
}

// Every point of the thesis's successful interval must succeed: 11 evenly spaced cases.
SweepAxis across(double first, double last) {
  return {first, last + 1e-9, (last - first) / 10.0};
}

void expect_all_succeed(const SweepResult& result) {
  ASSERT_EQ(result.points.size(), 11u);
  for (const auto& p : result.points) {
    EXPECT_TRUE(p.success) << "distance " << p.distance << " m, angle " << p.angle / kDeg << " deg: " << p.reason;
    if (p.detected) {
      EXPECT_LT(p.midpoint_error, 0.03);
      EXPECT_LT(std::abs(p.yaw_error), 2.0 * kDeg);
    }
  }
  // The longest run of successes is then the whole interval.
  ASSERT_TRUE(result.any);
  const bool by_angle = result.points.front().angle != result.points.back().angle;
  EXPECT_DOUBLE_EQ(result.lo, by_angle ? result.points.front().angle : result.points.front().distance);
  EXPECT_DOUBLE_EQ(result.hi, by_angle ? result.points.back().angle : result.points.back().distance);
}

}  // namespace

TEST(DetectionSweep, RealSenseCoversTheThesisTable71) {
  sim::DepthCamera camera(sim::realsense_r200(), 31);
  const perception::SweepSetup setup = setup_for(camera);
  // [Stacker thesis, Table 7.1]: 1.30-1.87 m at 0 deg; -8.0 to +4.7 deg at 1.63 m.
  expect_all_succeed(perception::sweep_distance(setup, across(1.30, 1.87)));
  expect_all_succeed(perception::sweep_angle(setup, 1.63, across(-8.0 * kDeg, 4.7 * kDeg)));
}

TEST(DetectionSweep, TofCameraCoversTheThesisTable72) {
  sim::DepthCamera camera(sim::sick_3vistor_t(std::numbers::pi / 2), 32);
  const perception::SweepSetup setup = setup_for(camera);
  // [Stacker thesis, Table 7.2]: 0.73-2.18 m at 0 deg; -12.3 to +14.8 deg at 2.18 m; -2.3 to
  // +4.7 deg at 0.73 m.
  expect_all_succeed(perception::sweep_distance(setup, across(0.73, 2.18)));
  expect_all_succeed(perception::sweep_angle(setup, 2.18, across(-12.3 * kDeg, 14.8 * kDeg)));
  expect_all_succeed(perception::sweep_angle(setup, 0.73, across(-2.3 * kDeg, 4.7 * kDeg)));
}

TEST(DetectionSweep, ReportsTheLongestRunOfSuccesses) {
  sim::DepthCamera camera(sim::sick_3vistor_t(std::numbers::pi / 2), 33);
  perception::SweepSetup setup = setup_for(camera);
  // Beyond the 7.2 m working distance nothing returns, so the run ends where the range does.
  const SweepResult r = perception::sweep_distance(setup, {1.5, 8.0, 0.5});
  ASSERT_TRUE(r.any);
  EXPECT_DOUBLE_EQ(r.lo, 1.5);
  EXPECT_LT(r.hi, 7.0);
  EXPECT_FALSE(r.points.back().success);
  EXPECT_FALSE(r.points.back().reason.empty());
}
