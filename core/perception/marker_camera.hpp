#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::perception {

/// A visual marker fixed to the front face of a pallet [Forklift thesis, section 6.2]. `pose` is the
/// marker's centre in the map frame; `pose.yaw` is the direction the printed face looks at, which
/// for a pallet is the side a forklift approaches from.
struct Marker {
  int id = 0;
  geometry::Pose2 pose;
};

/// One detected marker relative to the camera, the three numbers of [Forklift thesis, Fig. 6.6].
struct MarkerDetection {
  int id = 0;
  double time = 0.0;   ///< sim time of the frame, seconds
  double d = 0.0;      ///< distance camera -> marker centre, metres
  double alpha = 0.0;  ///< bearing of the marker from the optical axis, rad, positive to the left
  /// Orientation difference between marker and camera, rad: the rotation (counter-clockwise
  /// positive) that makes the optical axis anti-parallel to the marker's face normal, i.e. the
  /// camera square to the marker. Zero when looking straight at the printed face.
  double gamma = 0.0;
};

struct MarkerCameraParams {
  double rate_hz = 30.0;         ///< frame rate (camera 30 Hz [Forklift thesis, Table 3.1])
  double camera_x = 0.12;        ///< optical centre in the body frame, metres ahead of the centre
  double half_fov = 0.52;        ///< half horizontal field of view, rad (about 60 deg total)
  double range_min = 0.05;       ///< closer than this the marker overfills the image, metres
  double range_max = 0.80;       ///< farther than this it is too small to decode, metres
  double max_view_angle = 1.05;  ///< |gamma| beyond this the marker is too oblique to decode, rad
  double sigma_d = 0.002;        ///< distance noise, metres (1 sigma)
  double sigma_d_rel = 0.01;     ///< extra distance noise proportional to d
  double sigma_alpha = 0.004;    ///< bearing noise, rad
  double sigma_gamma = 0.015;    ///< relative-yaw noise, rad (pose-from-square is the weakest)
  double miss_rate = 0.05;       ///< probability a visible marker is not decoded in a frame
};

/// Simulated marker camera: from the robot's true pose and the true marker poses, returns what an
/// ArUco-style detector reports, with Gaussian noise and random misses (the thesis's detection
/// failed in poor light). Frames come at `rate_hz`; randomness comes from the seed given at
/// construction so a run is reproducible.
class MarkerCamera {
 public:
  MarkerCamera(MarkerCameraParams params, std::uint64_t seed);

  const MarkerCameraParams& params() const { return params_; }

  /// True when a frame is due at sim time `t` (the first call always is).
  bool frame_due(double t) const;

  /// Takes a frame at sim time `t`: the detections of every visible marker. Advances the frame
  /// clock, so call it only when frame_due(t).
  std::vector<MarkerDetection> capture(double t, const geometry::Pose2& robot_truth, std::span<const Marker> markers);

  /// The noise-free measurement of one marker, or false when it is outside the field of view,
  /// range or viewing angle. Deterministic; used by capture() and by tests.
  bool ideal_measurement(const geometry::Pose2& robot_truth, const Marker& marker, MarkerDetection& out) const;

 private:
  MarkerCameraParams params_;
  std::mt19937_64 rng_;
  double next_frame_time_ = -1.0e300;
};

/// The camera pose in the map frame for a robot at `robot`: same heading, `camera_x` ahead.
geometry::Pose2 camera_pose(const geometry::Pose2& robot, double camera_x);

/// Where a detection puts the marker in the map frame, given the robot pose it was taken from
/// (an estimate, in the agent). Inverse of the measurement model.
Marker marker_from_detection(const geometry::Pose2& robot, double camera_x, const MarkerDetection& det);

}  // namespace fleet::perception
