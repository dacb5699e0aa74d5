#include "eval/marker_loc_eval.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace fleet::eval {
namespace {

TEST(MarkerLocEval, RackMarkersKeepThePickersPoseBoundedWhereOdometryDrifts) {
  MarkerLocEvalParams params;
  params.duration = 400.0;  // four aisle lengths at the thesis's 0.3 m/s
  const MarkerLocEvalResult r = run_marker_loc_eval(params);
  EXPECT_GE(r.laps, 3);
  EXPECT_GT(r.distance_m, 90.0);
  EXPECT_EQ(r.markers_seen, 14) << "every pillar marker of both faces";
  EXPECT_LT(r.ekf.p95_cm, 10.0);
  EXPECT_LT(r.ekf.heading_max_deg, 3.0);
  EXPECT_LT(r.longest_gap_s, 15.0) << "the turns at the aisle ends included";
  EXPECT_GT(r.odometry.max_cm, 2.0 * r.ekf.max_cm) << "odometry alone drifts with roller slip";
}

TEST(MarkerLocEval, RefusesANonsenseRun) {
  MarkerLocEvalParams params;
  params.speed = 0.0;
  EXPECT_THROW(run_marker_loc_eval(params), std::invalid_argument);
  params.speed = 0.3;
  params.rack_distance = 2.0;
  EXPECT_THROW(run_marker_loc_eval(params), std::invalid_argument);
}

}  // namespace
}  // namespace fleet::eval
