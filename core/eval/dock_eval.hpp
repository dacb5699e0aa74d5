#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "control/docking_run.hpp"
#include "geometry/pose.hpp"
#include "perception/detection_sweep.hpp"

namespace fleet::eval {

/// The docking evaluation behind `fleetctl dock-eval`: the stacker's docking runs of [Stacker
/// thesis, section 7.2] on core/ alone, with the pallet found by the simulated depth cameras and
/// the detector, and the detection-range sweeps of [Stacker thesis, Tables 7.1 and 7.2].
///
/// The corridor frame: x along the finished-goods corridor, y across it, the limiter's edge at
/// y = 0 with the pallet row behind it (y < 0), the corridor 2.98 m wide [Stacker thesis,
/// section 4.1.2]. The target pallet's centre is at (11.6, -0.6), its entry face towards +y.
struct DockEvalParams {
  int runs = 54;  ///< the thesis's 6 starts x 9 pallet errors, repeated or cut to this many
  std::uint64_t seed = 1;
  /// The pose sensor standing in for GPS and compass: a few centimetres and about a degree.
  control::PoseSensorNoise pose_noise{0.03, 1.0 * 3.14159265358979323846 / 180.0};
  /// Detection runs at this rate (the cameras give 30 frames per second; one frame in six is
  /// enough for the law and keeps an evaluation short), Hz.
  double detection_rate_hz = 10.0;
  bool sweeps = true;        ///< also the detection-range sweeps
  bool trajectories = true;  ///< keep each run's path (for the plot)
};

/// One start of [Stacker thesis, section 7.2] in the corridor frame.
struct DockStart {
  std::string name;
  geometry::Pose2 pose;  ///< rear-axle midpoint
};

/// The two nominal starts (driving along the corridor near the limiter and on the far side the
/// other way) and the four off-nominal starts of section 7.2.2, mapped into the corridor frame.
std::vector<DockStart> dock_starts();
/// The logistics errors of section 7.2.3 along the row, metres: 0, +-0.20, +-0.40, +-0.60, +-0.66.
std::vector<double> dock_prior_errors();

struct DockRun {
  std::string start;
  double prior_error = 0.0;  ///< m
  std::uint64_t seed = 0;
  control::DockingRunResult result;
  int frames = 0;             ///< depth frames processed
  int frames_found = 0;       ///< frames with a detection
  std::string camera_report;  ///< what the cameras saw when no pallet was found
};

struct DockSummary {
  int runs = 0;
  int successes = 0;
  double success_rate = 0.0;
  double lateral_p95 = 0.0;  ///< |fork tips off the pocket centres|, m, over completed runs
  double lateral_max = 0.0;
  double yaw_p95 = 0.0;  ///< |yaw error|, rad
  double yaw_max = 0.0;
  double depth_p95 = 0.0;    ///< |fork depth error|, m
  double time_median = 0.0;  ///< s
  double time_p95 = 0.0;
  double path_median = 0.0;            ///< m
  double tolerated_prior_error = 0.0;  ///< the largest |logistics error| at which every run succeeded, m
};

/// A detection-range sweep beside the thesis's figure.
struct DockSweep {
  std::string name;  ///< e.g. "realsense distance at 0 deg"
  std::string unit;  ///< "m" or "deg"
  double seed_lo = 0.0;
  double seed_hi = 0.0;
  perception::SweepResult result;  ///< lo/hi in metres or radians
};

struct DockEvalResult {
  DockEvalParams params;
  geometry::Pose2 pallet;
  std::vector<DockRun> runs;
  DockSummary summary;
  std::vector<DockSweep> sweeps;
  double detect_ms_median = 0.0;  ///< one depth frame rendered and searched, wall milliseconds
};

/// One docking from `start` with the logistics pallet `prior_error` off along the row; `seed`
/// drives the pose sensor, the odometry and the cameras' noise. Adds its frame times (wall ms) to
/// `frame_ms` when given.
DockRun run_dock_case(const DockStart& start, double prior_error, const DockEvalParams& params, std::uint64_t seed,
                      std::vector<double>* frame_ms = nullptr);

DockEvalResult run_dock_eval(const DockEvalParams& params);

/// The runs' paths over the corridor, the pallet row and the limiter, as an SVG document.
std::string dock_eval_svg(const DockEvalResult& result);

}  // namespace fleet::eval
