#pragma once

#include <cstdint>
#include <map>
#include <random>
#include <span>
#include <utility>
#include <vector>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "perception/depth_image.hpp"

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
  double rate_hz = 30.0;           ///< frame rate (camera 30 Hz [Forklift thesis, Table 3.1])
  double camera_x = 0.12;          ///< optical centre in the body frame, metres ahead of the centre
  double camera_y = 0.0;           ///< optical centre in the body frame, metres to the left
  double camera_yaw = 0.0;         ///< optical axis in the body frame at pan 0, rad counter-clockwise
  double max_pan = 0.0;            ///< |pan| limit of a pan-tilt head, rad (0: a fixed camera)
  double half_fov = 0.52;          ///< half horizontal field of view, rad (about 60 deg total)
  double range_min = 0.05;         ///< closer than this the marker overfills the image, metres
  double range_max = 0.80;         ///< farther than this it is too small to decode, metres
  double max_view_angle = 1.05;    ///< |gamma| beyond this the marker is too oblique to decode, rad
  double sigma_d = 0.002;          ///< distance noise, metres (1 sigma)
  double sigma_d_rel = 0.01;       ///< extra distance noise proportional to d
  double sigma_d_quadratic = 0.0;  ///< extra distance noise proportional to d^2, per metre
  /// Systematic errors, fixed per marker for the whole run (its printed size and placement, the calibration):
  /// a distance error b + k max(0, d - exact_range) with b ~ N(0, sigma_d_bias) metres and
  /// k ~ N(0, sigma_d_bias_beyond) per metre, and a bearing offset ~ N(0, sigma_alpha_bias). Repeated frames
  /// of one marker do not average them away.
  double sigma_d_bias = 0.0;
  double sigma_d_bias_beyond = 0.0;
  double exact_range = 0.0;  ///< metres up to which the distance carries the constant bias b only
  double sigma_alpha_bias = 0.0;
  double sigma_alpha = 0.004;        ///< bearing noise, rad
  double sigma_gamma = 0.015;        ///< relative-yaw noise, rad (pose-from-square is the weakest)
  double miss_rate = 0.05;           ///< probability a visible marker is not decoded in a frame
  double miss_rate_per_speed = 0.0;  ///< extra miss probability per m/s of the robot (motion blur)

  /// The picker's Axis PTZ camera reading AR markers [Picker thesis, section 4.2.9.2.1, Tables 2-3]: detects
  /// to beyond 10 m, with a distance error below 30 cm up to about 5.5 m and about 1 m near 10 m, and drops
  /// frames at 1.0 m/s. Mounted at the base's front-right corner at 45° to its heading, panning ±180°.
  static MarkerCameraParams axis_ptz();

  /// Standard deviation of a detection's distance at `d`, per frame and systematic together: what a filter
  /// fusing the detection should assume.
  double distance_std(double d) const;
  /// Standard deviation of a detection's bearing, per frame and systematic together.
  double bearing_std() const;
};

/// Simulated marker camera: from the robot's true pose and the true marker poses, returns what an
/// ArUco-style detector reports, with Gaussian noise and random misses (the thesis's detection
/// failed in poor light). Frames come at `rate_hz`; randomness comes from the seed given at
/// construction so a run is reproducible.
class MarkerCamera {
 public:
  MarkerCamera(MarkerCameraParams params, std::uint64_t seed);

  const MarkerCameraParams& params() const { return params_; }

  /// Structures no camera sees through (rack rows): a marker behind one is not detected.
  void set_occluders(std::vector<geometry::Polygon> occluders) { occluders_ = std::move(occluders); }

  /// Turns a pan-tilt head to `pan` rad from its rest direction, clamped to ±max_pan.
  void set_pan(double pan);
  double pan() const { return pan_; }
  /// The camera's mount on the body at the current pan (a marker camera uses x, y and pan only).
  CameraMount mount() const;

  /// True when a frame is due at sim time `t` (the first call always is).
  bool frame_due(double t) const;

  /// Takes a frame at sim time `t`: the detections of every visible marker. Advances the frame
  /// clock, so call it only when frame_due(t).
  /// `speed` is the robot's speed over the floor, m/s, which blurs the image (miss_rate_per_speed).
  std::vector<MarkerDetection> capture(double t, const geometry::Pose2& robot_truth, std::span<const Marker> markers,
                                       double speed = 0.0);

  /// The noise-free measurement of one marker, or false when it is outside the field of view,
  /// range or viewing angle. Deterministic; used by capture() and by tests.
  bool ideal_measurement(const geometry::Pose2& robot_truth, const Marker& marker, MarkerDetection& out) const;

 private:
  MarkerCameraParams params_;
  std::mt19937_64 rng_;
  struct Bias {
    double d = 0.0;         ///< metres at any range
    double d_beyond = 0.0;  ///< metres per metre beyond exact_range
    double alpha = 0.0;
  };
  /// The systematic errors of a marker, drawn on its first sighting from their own engine, so that they do not
  /// reshuffle the per-frame noise.
  const Bias& bias_of(int marker_id);

  double next_frame_time_ = -1.0e300;
  double pan_ = 0.0;
  std::mt19937_64 bias_rng_;
  std::map<int, Bias> biases_;
  std::vector<geometry::Polygon> occluders_;
};

/// Turns a pan-tilt camera at the nearest of `markers` it could decode from a robot at `estimate` (face towards
/// the camera, within range and viewing angle once turned), as the picker's localization supervisor scans for
/// rack markers [Picker thesis, section 5.3.3.1, Fig. 5.3]. Returns the marker's id, or -1 (pan unchanged) when none
/// is. A marker `other_than` (another camera's) is passed over: two cameras on one marker give two of the three
/// pose coordinates, and the pose drifts about that marker under its systematic error.
int aim_at_nearest_marker(MarkerCamera& camera, const geometry::Pose2& estimate, std::span<const Marker> markers,
                          int other_than = -1);

/// The camera pose in the map frame for a robot at `robot`: same heading, `camera_x` ahead.
geometry::Pose2 camera_pose(const geometry::Pose2& robot, double camera_x);
/// The camera pose in the map frame for a robot at `robot` and a camera mounted at `mount`.
geometry::Pose2 camera_pose(const geometry::Pose2& robot, const CameraMount& mount);

/// Where a detection puts the marker in the map frame, given the robot pose it was taken from
/// (an estimate, in the agent). Inverse of the measurement model.
Marker marker_from_detection(const geometry::Pose2& robot, double camera_x, const MarkerDetection& det);
Marker marker_from_detection(const geometry::Pose2& robot, const CameraMount& mount, const MarkerDetection& det);

}  // namespace fleet::perception
