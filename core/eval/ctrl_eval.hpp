#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "control/path_follower.hpp"
#include "localization/ekf.hpp"
#include "perception/marker_camera.hpp"
#include "sim/forklift_body.hpp"
#include "sim/imu.hpp"
#include "sim/uwb.hpp"
#include "task/task_executor.hpp"

namespace fleet::eval {

/// The control evaluation behind `fleetctl ctrl-eval`, on core/ alone: the real forklift body
/// (mecanum kinematics, wheel lag, slip), UWB + gyro into the EKF, the marker camera, and the
/// controllers and task executor of the agent.
struct CtrlEvalParams {
  std::uint64_t seed = 1;
  int runs = 100;                 ///< pick-and-drop orders, one after another with the same pallets
  std::string site_file;          ///< e.g. maps/table_a.yaml; its road graph gives the paths
  double speed = 0.20;            ///< v_max of the follower, m/s
  double control_rate_hz = 70.0;  ///< pose and control rate [Forklift thesis, Table 3.1]
  /// Jitter of the pallets' starting poses around their areas (a previous, imperfect drop).
  double pallet_jitter = 0.005;           ///< metres, 1 sigma
  double pallet_yaw_jitter = 0.02;        ///< rad, 1 sigma
  double order_timeout = 240.0;           ///< sim seconds before an order counts as failed
  control::FollowerParams seed_follower;  ///< the thesis's follower
  control::FollowerParams regulated_follower = control::FollowerParams::regulated();  ///< with the extensions
  bool use_regulated = true;  ///< which of the two the pick-and-drop runs and the headline use
  /// Estimate the gyro bias whenever the robot stands still and subtract it before the EKF (the
  /// filter has no bias state, so a wandering bias turns into a heading error over a long run).
  /// Off by default: the agent does not do it; the flag shows what it would bring.
  bool gyro_standstill_calibration = false;
  sim::ForkliftParams forklift;
  sim::UwbParams uwb;
  sim::GyroParams gyro;
  localization::EkfParams ekf = localization::EkfParams::tuned();
  perception::MarkerCameraParams camera;
  task::ExecutorParams task;
};

/// One path followed once.
struct TrackingRun {
  std::string path;          ///< name of the standard path
  std::string follower;      ///< "seed" | "regulated"
  std::string localization;  ///< "perfect" | "ekf"
  double length = 0.0;       ///< metres
  double duration = 0.0;     ///< seconds from start to arrival
  bool arrived = false;
  double cross_track_rms = 0.0;  ///< true pose to the path polyline, metres
  double cross_track_max = 0.0;
  double loc_rms = 0.0;         ///< localization position error over the run, metres
  double omega_jump_max = 0.0;  ///< largest step-to-step change of the omega command, rad/s
  // For the plot, every 7th control step (10 Hz).
  std::vector<geometry::Pose2> path_poses;
  std::vector<geometry::Pose2> truth_track;
  std::vector<geometry::Pose2> estimate_track;
};

/// One order moving a pallet between two areas.
struct OrderRun {
  std::string pick_area;
  std::string drop_area;
  bool picked = false;  ///< the pallet really rose on the forks
  bool reported_picked = false;
  bool placed = false;                 ///< it was put down at the drop area
  double place_error = 0.0;            ///< pallet centre to the area, metres
  double place_yaw_error = 0.0;        ///< rad, absolute
  double pick_offset_lateral = 0.0;    ///< pallet on the forks, sideways, metres
  double pick_offset_yaw = 0.0;        ///< rad
  double loc_error_at_drop = 0.0;      ///< localization position error when the forks lowered, m
  double loc_yaw_error_at_drop = 0.0;  ///< localization heading error then, rad, signed
  double duration = 0.0;
  std::string failure;
};

struct Percentiles {
  double p50 = 0.0;
  double p95 = 0.0;
  double max = 0.0;
};

struct CtrlEvalResult {
  CtrlEvalParams params;
  std::vector<TrackingRun> tracking;
  std::vector<OrderRun> orders;
  // Headline: EKF localization, the follower selected by use_regulated, all standard paths.
  double cross_track_rms = 0.0;
  double cross_track_max = 0.0;
  double cross_track_rms_perfect = 0.0;
  double cross_track_max_perfect = 0.0;
  Percentiles place_error;      ///< metres, over placed orders
  Percentiles place_yaw_error;  ///< degrees
  int picks = 0;                ///< orders whose pallet really rose on the forks
  double pick_success = 0.0;    ///< picks / runs
  int places = 0;
  // The same orders with perfect localization: what the controllers alone achieve.
  Percentiles perfect_place_error;
  Percentiles perfect_place_yaw_error;
  double perfect_pick_success = 0.0;
};

/// The standard paths on a site's road graph, named; for table_a a lap of the ring road (its
/// four 15 cm-radius corners) and a route through the T-junctions and the central crossing.
struct NamedPath {
  std::string name;
  std::vector<geometry::Pose2> poses;
};
std::vector<NamedPath> standard_paths(const std::string& site_file);

/// Distance from `p` to the polyline through `path`.
double distance_to_path(const std::vector<geometry::Pose2>& path, geometry::Vec2 p);

/// The headline follower's EKF runs as a standalone SVG: planned path, true track and estimate
/// on the site (like [Forklift thesis, Fig. 6.5a]).
std::string ctrl_eval_svg(const CtrlEvalResult& result);

/// Runs everything. Throws std::invalid_argument for bad parameters and map::MapError for an
/// unusable site.
CtrlEvalResult run_ctrl_eval(const CtrlEvalParams& params);

}  // namespace fleet::eval
