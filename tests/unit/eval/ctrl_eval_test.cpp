#include "eval/ctrl_eval.hpp"

#include <gtest/gtest.h>

#include <string>

#include "test_paths.hpp"

namespace fleet::eval {
namespace {

const std::string kSite = fleet::test::source_dir() + "/maps/table_a.yaml";

TEST(CtrlEval, DistanceToPath) {
  const std::vector<geometry::Pose2> path{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  EXPECT_NEAR(distance_to_path(path, {0.5, 0.2}), 0.2, 1e-12);
  EXPECT_NEAR(distance_to_path(path, {1.3, 0.5}), 0.3, 1e-12);
  EXPECT_NEAR(distance_to_path(path, {-0.3, -0.4}), 0.5, 1e-12);
}

TEST(CtrlEval, StandardPathsFollowTableARoads) {
  const auto paths = standard_paths(kSite);
  ASSERT_EQ(paths.size(), 2u);
  for (const auto& p : paths) {
    double len = 0.0;
    for (std::size_t i = 1; i < p.poses.size(); ++i) {
      len += geometry::distance(p.poses[i - 1].position(), p.poses[i].position());
      // Road-graph samples: about 10 cm apart, never a jump across the table.
      EXPECT_LT(geometry::distance(p.poses[i - 1].position(), p.poses[i].position()), 0.16) << p.name;
    }
    EXPECT_GT(len, 5.0) << p.name;
  }
}

TEST(CtrlEval, SmallRunMeetsTheTargetsAndIsReproducible) {
  CtrlEvalParams params;
  params.site_file = kSite;
  params.runs = 4;
  params.seed = 3;
  const CtrlEvalResult a = run_ctrl_eval(params);
  ASSERT_EQ(a.tracking.size(), 8u);
  for (const auto& t : a.tracking) EXPECT_TRUE(t.arrived) << t.path << " " << t.follower << " " << t.localization;
  // The targets for tracking with the EKF at 0.2 m/s.
  EXPECT_LE(a.cross_track_rms, 0.02);
  EXPECT_LE(a.cross_track_max, 0.05);
  EXPECT_LE(a.cross_track_rms_perfect, 0.01);
  // The regulated follower's omega never jumps more than its acceleration limit allows.
  for (const auto& t : a.tracking) {
    if (t.follower == "regulated") {
      EXPECT_LE(t.omega_jump_max, params.regulated_follower.max_angular_accel / params.control_rate_hz + 1e-9);
    }
  }
  ASSERT_EQ(a.orders.size(), 4u);
  EXPECT_DOUBLE_EQ(a.pick_success, 1.0);
  EXPECT_DOUBLE_EQ(a.perfect_pick_success, 1.0);
  // With perfect localization the placement error is the controllers' own.
  EXPECT_LE(a.perfect_place_error.p95, 0.015);
  EXPECT_LE(a.perfect_place_yaw_error.p95, 3.0);

  const CtrlEvalResult b = run_ctrl_eval(params);
  EXPECT_DOUBLE_EQ(a.cross_track_rms, b.cross_track_rms);
  EXPECT_DOUBLE_EQ(a.place_error.p95, b.place_error.p95);
}

TEST(CtrlEval, RejectsBadParameters) {
  CtrlEvalParams params;
  params.site_file = kSite;
  params.runs = -1;
  EXPECT_THROW(run_ctrl_eval(params), std::invalid_argument);
  params.runs = 1;
  params.site_file.clear();
  EXPECT_THROW(run_ctrl_eval(params), std::invalid_argument);
}

}  // namespace
}  // namespace fleet::eval
