// The docking evaluation end to end on core/: the stacker's body, the docking law, the depth
// cameras rendering the pallet row and the detector finding the pallet in their frames.

#include "eval/dock_eval.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geometry/pose.hpp"
#include "sim/tricycle.hpp"

namespace fleet::eval {
namespace {

using ::fleet::geometry::kDeg;

TEST(DockEval, TheMatrixIsTheThesisSixStartsByNinePalletErrors) {
  const auto starts = dock_starts();
  const auto errors = dock_prior_errors();
  EXPECT_EQ(starts.size() * errors.size(), 54u);
  // Every start's chassis stands inside the 2.98 m corridor.
  const sim::TricycleGeometry g;
  for (const auto& s : starts) {
    for (const auto& corner : sim::polygon_in_map(s.pose, sim::tricycle_chassis(g))) {
      EXPECT_GE(corner.y, 0.0) << s.name;
      EXPECT_LE(corner.y, 2.98) << s.name;
    }
  }
}

// A nominal start and an off-nominal one at the largest logistics errors, with the default pose
// noise: the camera finds the right pallet and the forks end in its pockets within the targets.
TEST(DockEval, DocksAtTheLargestLogisticsErrorsWithPoseNoise) {
  DockEvalParams params;
  params.trajectories = false;
  const auto starts = dock_starts();
  std::uint64_t seed = 11;
  for (const auto& start : {starts[1], starts[4]}) {
    for (double error : {0.66, -0.66}) {
      const DockRun run = run_dock_case(start, error, params, seed++);
      EXPECT_TRUE(run.result.success) << run.start << " " << error << ": " << run.result.failure_reason;
      EXPECT_LT(std::abs(run.result.lateral_error), 0.02) << run.start << " " << error;
      EXPECT_LT(std::abs(run.result.yaw_error), 0.5 * kDeg) << run.start << " " << error;
      EXPECT_GT(run.frames_found, 10) << run.start << " " << error;
    }
  }
}

// Beyond half the row's pitch the neighbour is nearer the logistics position than the pallet:
// the stacker docks there, as the thesis's did beyond 0.66 m, and the run says it missed.
TEST(DockEval, ALogisticsErrorBeyondHalfThePitchDocksAtTheNeighbour) {
  DockEvalParams params;
  params.trajectories = false;
  params.pose_noise = {};
  const DockRun run = run_dock_case(dock_starts()[0], 0.95, params, 5);
  EXPECT_FALSE(run.result.success);
  EXPECT_NEAR(std::abs(run.result.lateral_error), 1.5, 0.05);
}

}  // namespace
}  // namespace fleet::eval
