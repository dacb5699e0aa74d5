#include "eval/loc_eval.hpp"

#include <gtest/gtest.h>

#include <algorithm>

using namespace fleet::eval;

TEST(LocEval, Figure8MeetsTheAccuracyTargets) {
  // The accuracy targets hold on figure8, 60 s, seed 1, default noise.
  LocEvalParams p;
  p.trajectory = Trajectory::kFigure8;
  p.duration = 60.0;
  p.seed = 1;
  const LocEvalResult r = run_loc_eval(p);
  EXPECT_NEAR(r.range_noise_std, 0.05, 0.005);
  EXPECT_GT(r.uwb_fixes, 1100);
  EXPECT_LE(r.full.ekf.pos_rmse, 0.5 * r.uwb.pos_rmse);
  EXPECT_LE(r.full.ekf.heading_rmse_deg, 3.0);
  EXPECT_GT(r.full.ekf.heading_samples, 0.9 * r.full.ekf.samples);
}

TEST(LocEval, Figure8TargetsHoldForOtherSeeds) {
  for (std::uint64_t seed : {2u, 3u, 4u}) {
    LocEvalParams p;
    p.seed = seed;
    p.variants = false;
    const LocEvalResult r = run_loc_eval(p);
    EXPECT_LE(r.full.ekf.pos_rmse, 0.5 * r.uwb.pos_rmse) << "seed " << seed;
    EXPECT_LE(r.full.ekf.heading_rmse_deg, 3.0) << "seed " << seed;
  }
}

TEST(LocEval, GatingKeepsTheErrorNearTheCleanRunWithNlosRanges) {
  LocEvalParams p;
  p.duration = 60.0;
  p.seed = 1;
  const LocEvalResult clean = run_loc_eval(p);
  p.nlos_fraction = 0.1;
  const LocEvalResult nlos = run_loc_eval(p);
  EXPECT_GT(nlos.nlos_ranges, 0.07 * nlos.ranges);
  EXPECT_LE(nlos.full.ekf.pos_rmse, 1.3 * clean.full.ekf.pos_rmse);
  // With Q_t fixed as in the thesis, gating is what keeps NLOS fixes out.
  const VariantResult* gated = nullptr;
  const VariantResult* open = nullptr;
  for (const auto& v : nlos.variants) {
    if (v.name == "fixed_q") gated = &v;
    if (v.name == "fixed_q_no_gating") open = &v;
  }
  ASSERT_TRUE(gated && open);
  EXPECT_GT(gated->fixes_gated, 0);
  EXPECT_LT(gated->ekf.pos_rmse, open->ekf.pos_rmse);
}

TEST(LocEval, IsReproducibleFromTheSeedAndRunsEveryTrajectory) {
  for (const Trajectory t : {Trajectory::kSquare, Trajectory::kFigure8, Trajectory::kTableALoop}) {
    LocEvalParams p;
    p.trajectory = t;
    p.duration = 10.0;
    p.seed = 3;
    p.variants = false;
    const LocEvalResult a = run_loc_eval(p);
    const LocEvalResult b = run_loc_eval(p);
    EXPECT_EQ(a.full.ekf.pos_rmse, b.full.ekf.pos_rmse);
    EXPECT_EQ(a.uwb.pos_rmse, b.uwb.pos_rmse);
    EXPECT_TRUE(a.variants.empty());
    // The forklift stays on the table.
    for (const auto& pose : a.truth) {
      EXPECT_GT(pose.x, 0.2);
      EXPECT_LT(pose.x, 2.8);
      EXPECT_GT(pose.y, 0.2);
      EXPECT_LT(pose.y, 2.8);
    }
    p.seed = 4;
    EXPECT_NE(run_loc_eval(p).uwb.pos_rmse, a.uwb.pos_rmse);
  }
}

TEST(LocEval, RejectsBadParameters) {
  LocEvalParams p;
  p.duration = 0.0;
  EXPECT_THROW(run_loc_eval(p), std::invalid_argument);
  p.duration = 5.0;
  p.nlos_fraction = 1.5;
  EXPECT_THROW(run_loc_eval(p), std::invalid_argument);
  EXPECT_EQ(parse_trajectory("figure8"), Trajectory::kFigure8);
  EXPECT_FALSE(parse_trajectory("circle"));
}

TEST(LocEval, SvgShowsTruthFixesAndTrack) {
  LocEvalParams p;
  p.duration = 5.0;
  p.variants = false;
  const LocEvalResult r = run_loc_eval(p);
  const std::string svg = loc_eval_svg(r);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(std::count(svg.begin(), svg.end(), '\n') > 50, true);
  EXPECT_NE(svg.find("stroke=\"black\""), std::string::npos);    // truth
  EXPECT_NE(svg.find("stroke=\"#1f77b4\""), std::string::npos);  // EKF
  EXPECT_NE(svg.find("<circle"), std::string::npos);             // UWB fixes
}

TEST(LocEval, WheelEncodersCanReplaceTheCommandedVelocity) {
  LocEvalParams p;
  p.duration = 30.0;
  p.encoders.enabled = true;
  const LocEvalResult r = run_loc_eval(p);
  const VariantResult* enc = nullptr;
  for (const auto& v : r.variants) {
    if (v.name == "encoders") enc = &v;
  }
  ASSERT_TRUE(enc);
  EXPECT_LE(enc->ekf.pos_rmse, 0.5 * r.uwb.pos_rmse);
  EXPECT_LE(enc->ekf.heading_rmse_deg, 3.0);
}
