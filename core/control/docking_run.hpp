#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "control/docking_law.hpp"
#include "geometry/pose.hpp"
#include "sim/tricycle.hpp"

namespace fleet::control {

/// Gives this period's pallet detection, if any: the pallet's centre and entry-axis yaw in the map frame.
/// `vehicle` is the true pose of the rear-axle midpoint, `expected` the pallet pose the law currently steers by (a
/// detector searches a region of interest round it [Stacker thesis, section 6.2.1]), `time` the run's clock in s.
/// A camera-based detector can be plugged in here.
using PalletDetector = std::function<std::optional<geometry::Pose2>(const geometry::Pose2& vehicle,
                                                                    const geometry::Pose2& expected, double time)>;

/// A stand-in for the thesis's ToF and RealSense pallet detection [Stacker thesis, sections 5.4, 6.2]: it sees the
/// pallets of a row within a range of the rear axle and returns the one nearest the expected pose if it lies in
/// the region of interest, with Gaussian noise. Neighbours in the row make a large logistics error dock at the
/// wrong pallet, as in [Stacker thesis, section 7.2.3].
struct SimulatedDetectorParams {
  double position_noise = 0.0;   ///< std of x and y, m
  double yaw_noise = 0.0;        ///< std, rad
  double min_range = 0.3;        ///< rear axle to the entry-face midpoint, m
  double max_range = 4.0;        ///< m
  double roi_radius = 0.7;       ///< m
  double neighbour_pitch = 1.4;  ///< centre to centre along the row, m (0: a lone pallet)
  int neighbours_each_side = 1;
  double pallet_depth = 1.2;  ///< m
};

PalletDetector make_simulated_detector(const geometry::Pose2& pallet, const SimulatedDetectorParams& params,
                                       std::uint64_t seed);

/// The pose sensor that stands in for the thesis's GPS and compass [Stacker thesis, section 8.1]:
/// the true pose plus a Gaussian error of these standard deviations. Zero gives the thesis's exact
/// pose.
struct PoseSensorNoise {
  double position_sigma = 0.0;  ///< m, per axis
  double yaw_sigma = 0.0;       ///< rad
};

/// The drive wheel's encoder and the steering angle sensor, integrated: each step's motion with a
/// white error proportional to its length.
struct OdometryNoise {
  double distance_fraction = 0.01;  ///< std of the position error per metre driven
  double yaw_per_metre = 0.01;      ///< std of the heading error per metre driven, rad
};

struct DockingRunParams {
  DockingParams law;
  sim::TricycleParams vehicle;
  SimulatedDetectorParams detector;
  /// Logistics error of the pallet position along the row (the thesis's y error [Stacker thesis, section 7.2.3]), m.
  /// The law starts from the pallet shifted by this much to the left of its entry axis.
  double prior_error = 0.0;
  /// The law works in the odometry frame anchored where the pose sensor puts the vehicle when
  /// docking starts: the sensor's error shifts only where the logistics pallet is looked for,
  /// and the detections, measured from the vehicle, are placed by odometry (the truth moves the
  /// body). A docking is relative to the pallet; a wandering absolute pose would blur it.
  PoseSensorNoise pose_noise;
  OdometryNoise odometry_noise;
  std::uint64_t pose_seed = 1;
  double control_period = 0.05;     ///< s
  double trajectory_period = 0.25;  ///< s between recorded samples; 0 records none
  double success_lateral = 0.02;    ///< fork tips off the pocket centres, m (the project's target)
  double success_yaw = 0.0087266;   ///< rad (0.5 deg, the project's target)
};

struct DockingSample {
  double time = 0.0;
  geometry::Pose2 pose;  ///< true rear-axle midpoint
  sim::TricycleCommand command;
  DockingPhase phase = DockingPhase::kToTarget1;
};

struct DockingRunResult {
  bool completed = false;  ///< the law reached kDone
  bool success = false;    ///< completed, at the right pallet, within the lateral and yaw targets
  DockingPhase final_phase = DockingPhase::kToTarget1;
  std::string failure_reason;
  double time = 0.0;           ///< s
  double lateral_error = 0.0;  ///< fork-tip midpoint off the pallet axis (= each tip off its pocket centre), m
  double yaw_error = 0.0;      ///< stacker yaw minus pallet yaw, rad
  double depth_error = 0.0;    ///< fork tips deeper (+) or shallower than the pocket depth, m
  double path_length = 0.0;    ///< of the rear-axle midpoint, m
  int realignments = 0;
  int detections = 0;
  geometry::Pose2 final_pose;
  std::vector<DockingSample> trajectory;
};

/// One docking with the simulated stacker, the simulated detector seeded by `seed` and the logistics error of
/// `params.prior_error`. `pallet` is the true pallet pose.
DockingRunResult simulate_docking(const geometry::Pose2& start, const geometry::Pose2& pallet,
                                  const DockingRunParams& params, std::uint64_t seed);

/// The same with any detector and prior.
DockingRunResult simulate_docking(const geometry::Pose2& start, const geometry::Pose2& pallet,
                                  const geometry::Pose2& pallet_prior, const DockingRunParams& params,
                                  const PalletDetector& detector);

}  // namespace fleet::control
