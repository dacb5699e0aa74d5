#include "eval/marker_loc_eval.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <stdexcept>

#include "geometry/pose.hpp"
#include "localization/marker_localizer.hpp"
#include "sim/summit_xls.hpp"

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

/// The largest heading error (rad) over the last half of `seconds` standing still in the rack aisle, a gyro
/// whose bias starts `bias` rad/s off and wanders; `in_sight` false hides every marker.
double heading_error_standing(localization::MarkerLocalizerParams params, double bias, double seconds,
                              bool in_sight = true) {
  const MarkerLocEvalParams aisle;
  std::vector<perception::Marker> markers;
  for (const auto& m : rack_aisle_markers(aisle)) markers.push_back({m.id, m.pose});
  if (!in_sight) markers.clear();
  params.gyro->bias_initial_std = bias;
  const geometry::Pose2 here{44.0, aisle.south_face_y + aisle.rack_distance, std::numbers::pi};
  localization::MarkerLocalizer localizer(params, sim::summit_xls_body_params().mecanum, here, markers, {},
                                          std::mt19937_64(7));
  constexpr double kPeriod = 1.0 / 70.0;
  double worst = 0.0;
  const int steps = static_cast<int>(seconds / kPeriod);
  for (int i = 1; i <= steps; ++i) {
    localizer.step(i * kPeriod, kPeriod, {}, {}, here, 0.0, 0.0);
    if (i > steps / 2) worst = std::max(worst, std::abs(geometry::angle_diff(localizer.ekf().pose().yaw, here.yaw)));
  }
  return worst;
}

using ::fleet::geometry::kDeg;

TEST(MarkerLocalizer, AStandingPickerKeepsItsHeadingOnTwoMarkers) {
  // Ten minutes waiting for traffic in the aisle, a gyro bias three times the typical residual. The two
  // cameras look at two markers: on one marker the pose is two of three coordinates, and it turned about
  // that marker under its systematic error (85 deg in ten minutes).
  localization::MarkerLocalizerParams params;
  const double worst = heading_error_standing(params, 3.0 * params.gyro->bias_initial_std, 600.0);
  std::cout << "standing 600 s in the aisle: heading off by " << worst / kDeg << " deg at worst\n";
  EXPECT_LT(worst, 1.5 * kDeg);
}

TEST(MarkerLocalizer, EveryStopCalibratesTheGyroWhereNoMarkerIsInSight) {
  localization::MarkerLocalizerParams params;
  const double bias = 3.0 * params.gyro->bias_initial_std;
  const double calibrated = heading_error_standing(params, bias, 120.0, false);
  params.ekf.gyro_bias = false;
  params.ekf.standstill_update = false;
  const double drifting = heading_error_standing(params, bias, 120.0, false);
  std::cout << "standing 120 s, no marker in sight, gyro bias " << bias << " rad/s: heading off by "
            << calibrated / kDeg << " deg with the bias estimated at rest, " << drifting / kDeg << " deg without\n";
  EXPECT_LT(calibrated, 0.5 * kDeg);
  EXPECT_GT(drifting, 10.0 * calibrated);
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
