#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::perception {

/// A marker printed on the top face of a box on a pallet [Picker thesis, section 4.4]: its centre is the face's
/// centre, its yaw the direction of the face's length; map frame, z up from the floor.
struct BoxMarker {
  int id = 0;
  Eigen::Vector3d top_centre = Eigen::Vector3d::Zero();
  double yaw = 0.0;
};

/// A box marker as a depth camera locates it, carried through the frames camera -> pan-tilt unit -> boom ->
/// mobile base [Picker thesis, section 4.4.1]: the top face's centre and yaw in the mobile base's frame (x ahead,
/// y left, z up from the floor), what the arm's planner takes (arm::BoxPlacement).
struct BoxSighting {
  int id = 0;
  double time = 0.0;      ///< sim time of the frame, s
  double distance = 0.0;  ///< camera -> marker, m
  Eigen::Vector3d top_centre = Eigen::Vector3d::Zero();
  double yaw = 0.0;
};

/// One Orbbec Astra on its boom [Picker thesis, section 3.1.1]: 0.6-8 m, 60° x 49.5°, 640 x 480 at 30 fps, on a
/// pan-tilt unit at the top of a 1.5 m boom at the base's front. Experiment 1 [Picker thesis, section 4.2.9.2.1] read
/// markers with it to 6.5 m at 0.3 m/s and to about 3 m at 1.0 m/s.
struct DepthMarkerCameraParams {
  double rate_hz = 30.0;
  Eigen::Vector3d mount{0.25, -0.20, 1.50};  ///< the pan-tilt unit on the right boom, base frame, m
  double half_hfov = 0.5236;                 ///< 30°
  double half_vfov = 0.4320;                 ///< 24.75°
  double range_min = 0.6;                    ///< m
  double range_max = 8.0;                    ///< m
  /// Reading range with the robot moving: 6.5 m at 0.3 m/s, 3.0 m at 1.0 m/s, linear between (and beyond,
  /// within [range_min, range_max]).
  double read_range_slow = 6.5;
  double read_range_fast = 3.0;
  double max_view_angle = 1.05;  ///< a marker seen more than 60° off its normal is not decoded, rad
  /// Position error per axis: sigma_position + sigma_position_quadratic * d^2 (a structured-light camera's depth
  /// error grows with the square of the range); the seed gives none.
  double sigma_position = 0.002;             ///< m
  double sigma_position_quadratic = 0.0015;  ///< per m
  double sigma_yaw = 0.0175;                 ///< rad, 1°
  double miss_rate = 0.05;

  /// How far a marker is read at `speed` m/s.
  double read_range(double speed) const;
};

/// The simulated depth camera reading box markers: from the robot's true pose and the true boxes, the sightings an
/// AR-marker detector on its RGB-D image reports, with seeded Gaussian noise and misses.
class DepthMarkerCamera {
 public:
  /// Throws std::invalid_argument for a non-positive rate, an empty range or a miss rate outside [0, 1].
  DepthMarkerCamera(DepthMarkerCameraParams params, std::uint64_t seed);

  const DepthMarkerCameraParams& params() const { return params_; }
  /// Turns the pan-tilt unit so that the optical axis points at `target` (base frame).
  void look_at(const Eigen::Vector3d& target);
  double pan() const { return pan_; }
  double tilt() const { return tilt_; }

  bool frame_due(double t) const { return t >= next_frame_; }
  /// One frame at sim time `t` (call when frame_due): every marker in view, range and viewing angle, read.
  std::vector<BoxSighting> capture(double t, const geometry::Pose2& robot_truth, std::span<const BoxMarker> markers,
                                   double speed = 0.0);
  /// The noise-free sighting of `marker`, or false when the camera cannot read it. Deterministic.
  bool ideal(const geometry::Pose2& robot_truth, const BoxMarker& marker, double speed, BoxSighting& out) const;

 private:
  DepthMarkerCameraParams params_;
  std::mt19937_64 rng_;
  double next_frame_ = -1.0e300;
  double pan_ = 0.0;
  double tilt_ = 0.0;
};

}  // namespace fleet::perception
