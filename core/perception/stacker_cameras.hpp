#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "perception/pallet_detector.hpp"
#include "sim/depth_camera.hpp"
#include "sim/tricycle.hpp"

namespace fleet::perception {

/// The stacker's two depth cameras with their mounts in the frame of the rear-axle midpoint
/// [Stacker thesis, section 4.2.2]: the 3Vistor-T on the pan-tilt unit at the front, between the
/// chassis front and the fork tips' midpoint, and the RealSense R200 at the chassis back face where
/// the forks begin, looking backwards between them. The presets place a camera on a body whose
/// origin is the vehicle's centre; these move it to the rear-axle frame.
sim::DepthCameraParams stacker_tof(const sim::TricycleGeometry& geometry);
sim::DepthCameraParams stacker_rear_camera(const sim::TricycleGeometry& geometry);

/// The pallets one docking may see: a row on the limiter or on the floor, as a ray-cast scene.
struct PalletRow {
  sim::DepthScene scene;
  double base_height = 0.0;  ///< what the pallets stand on, metres (0.30 on the limiter)
};

struct StackerDetectorParams {
  /// Depth frames are searched at this rate; the cameras give 30 frames per second, one in three
  /// or six is enough for the law and keeps the simulation cheap, Hz.
  double rate_hz = 10.0;
  /// The docking area round the logistics position [Stacker thesis, section 6.3]: half the row's
  /// pitch along the face, so that a neighbour is never taken for the target.
  DockingArea area{0.35, 0.65};
  /// A tracked pallet further than this from where the law expects it is not the one it
  /// expects: the search starts afresh there, m.
  double track_radius = 0.3;
};

/// The camera-based pallet detector of one docking: each call at the detection rate renders the
/// camera that faces the expected pallet (the RealSense when the pallet is behind, else the ToF
/// panned towards it [Stacker thesis, section 6.3]) and searches the frame [Stacker thesis, sections 5.4, 6.2];
/// in between it reports nothing. The region of interest follows the last detection while it is
/// the pallet the law expects [Stacker thesis, section 6.2.1].
class StackerCameraDetector {
 public:
  StackerCameraDetector(const sim::TricycleGeometry& geometry, PalletRow row, const StackerDetectorParams& params,
                        std::uint64_t seed);

  /// This period's detection (pallet centre and entry-axis yaw, map frame) for the stacker at
  /// `vehicle` (true rear-axle pose) looking for the pallet at `expected`, at time `t` seconds.
  std::optional<geometry::Pose2> operator()(const geometry::Pose2& vehicle, const geometry::Pose2& expected, double t);

  int frames() const { return frames_; }
  int found() const { return found_; }
  /// Which camera looked last and why it found nothing, for a "pallet not found" report.
  const std::string& last_reason() const { return last_reason_; }
  /// Wall milliseconds of each frame rendered and searched.
  const std::vector<double>& times_ms() const { return times_ms_; }

 private:
  sim::DepthCamera& pick_camera(geometry::Vec2 face);

  sim::DepthCamera tof_;
  sim::DepthCamera rear_;
  PalletRow row_;
  StackerDetectorParams params_;
  double next_ = 0.0;
  std::optional<geometry::Pose2> last_;
  int frames_ = 0;
  int found_ = 0;
  std::string last_reason_;
  std::vector<double> times_ms_;
};

}  // namespace fleet::perception
