#pragma once

#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "perception/depth_image.hpp"
#include "perception/pallet_detector.hpp"

namespace fleet::perception {

/// Renders the depth image a camera sees of one pallet at `pallet_in_robot` (footprint centre,
/// robot frame). The simulator provides it; the sweep only moves the pallet.
using PalletFrameRenderer = std::function<DepthImage(const geometry::Pose2& pallet_in_robot)>;

/// The experiment of [Stacker thesis, section 7.1.1, Tables 7.1 and 7.2]: a pallet straight
/// ahead of the camera, its entry face towards it, moved away or turned.
struct SweepSetup {
  DepthCameraModel camera;
  PalletFrameRenderer render;
  PalletDetectorParams detector;
  DockingArea area;
  double base_height = 0.0;  ///< what the pallet stands on
  /// A detection succeeds when it is this close to the truth. The thesis only says the features
  /// were "retrieved correctly"; a few centimetres and a couple of degrees is what its final
  /// alignment needs.
  double midpoint_tolerance = 0.03;                       ///< metres
  double yaw_tolerance = 2.0 * std::numbers::pi / 180.0;  ///< rad
};

struct SweepAxis {
  double first = 0.0;
  double last = 0.0;
  double step = 0.0;
};

struct SweepPoint {
  double distance = 0.0;  ///< horizontal, camera optical centre to the middle of the pallet face, metres
  double angle = 0.0;     ///< pallet turned counter-clockwise about its centre, rad
  bool detected = false;
  bool success = false;         ///< detected and within the tolerances
  double midpoint_error = 0.0;  ///< metres (when detected)
  double yaw_error = 0.0;       ///< rad (when detected)
  std::string reason;           ///< the detector's, or which tolerance failed
};

struct SweepResult {
  std::vector<SweepPoint> points;
  /// The longest run of consecutive successes: its first and last distance (or angle).
  bool any = false;
  double lo = 0.0;
  double hi = 0.0;
};

/// The pallet pose (footprint centre, robot frame) `distance` ahead of the camera along its pan
/// direction, turned by `angle` about its own centre, its entry face towards the camera.
geometry::Pose2 pallet_ahead_of_camera(const DepthCameraModel& camera, double distance, double angle,
                                       double pallet_length = 1.2);

/// Sweeps the distance with the pallet square to the camera (Stacker thesis, Tables 7.1 and 7.2, first rows).
SweepResult sweep_distance(const SweepSetup& setup, SweepAxis distances);
/// Sweeps the pallet's angle at a fixed distance (Stacker thesis, Tables 7.1 and 7.2, other rows). The detector
/// expects the pallet square to the camera, as a logistics position would have it.
SweepResult sweep_angle(const SweepSetup& setup, double distance, SweepAxis angles);

}  // namespace fleet::perception
