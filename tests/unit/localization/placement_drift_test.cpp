// Regression for the placement misses of ctrl-eval (issue 6): a gyro bias wandering over a long
// shift, integrated by a filter without a bias state, and the steady UWB offset of eq. 2.8, put
// pallets 3.6 cm / 14.5 degrees off (p95) on seed 1. The filter's defaults must meet the
// placement targets there.
#include <gtest/gtest.h>

#include <string>

#include "control/ctrl_eval.hpp"

namespace {

TEST(PlacementDrift, DefaultFilterMeetsThePlacementTargetsOnSeed1) {
  fleet::control::CtrlEvalParams params;
  params.site_file = std::string(FLEET_SOURCE_DIR) + "/maps/table_a.yaml";
  params.seed = 1;
  params.runs = 60;  // long enough for the bias to wander (about 20 minutes of simulated shift)
  const fleet::control::CtrlEvalResult r = fleet::control::run_ctrl_eval(params);
  EXPECT_GE(r.pick_success, 0.98);
  EXPECT_LE(r.place_error.p95, 0.02);
  EXPECT_LE(r.place_yaw_error.p95, 3.0);
  EXPECT_LE(r.cross_track_rms, 0.02);
  EXPECT_LE(r.cross_track_max, 0.05);
}

}  // namespace
