#pragma once

#include <array>
#include <numbers>
#include <optional>
#include <string>

#include "geometry/pose.hpp"
#include "perception/depth_image.hpp"

namespace fleet::perception {

/// What the detector expects of the pallet face the forks enter: an EPAL 800 mm face (EN 13698-1)
/// shows three columns and two fork pockets 100 mm high. The thesis's model has three equal
/// columns [Stacker thesis, section 5.4]; a real EPAL's outer columns are 100 mm, the middle one
/// 145 mm, and the pockets 227.5 mm.
struct PalletFaceModel {
  double length = 1.200;  ///< pallet centre to this face is half of it, metres
  double width = 0.800;   ///< the face, metres
  double height = 0.144;
  double outer_column = 0.100;
  double middle_column = 0.145;
  double pocket = 0.2275;
  double pocket_height = 0.100;  ///< floor to the underside of the cross board
};

/// The region where the pallet must be for a detection to count, centred on the expected face
/// midpoint and aligned with the expected face [Stacker thesis, section 6.3: detections are
/// accepted only inside the expected docking area].
struct DockingArea {
  double depth_half = 0.30;    ///< along the face normal, metres
  double lateral_half = 0.50;  ///< along the face, metres (logistics errs by up to 0.5 m
                               ///< [Stacker thesis, section 5.3.1])
  double yaw_half = 20.0 * std::numbers::pi / 180.0;  ///< rad
};

/// Where the caller expects the pallet, in the robot frame.
struct PalletExpectation {
  /// Expected pallet footprint centre; yaw along the pallet's length. The detector looks at
  /// whichever 800 mm face turns towards the camera.
  geometry::Pose2 pallet;
  double base_height = 0.0;  ///< height of what it stands on (0.30 m on the limiter [Stacker thesis, section 4.1.3])
  DockingArea area;
  /// When tracking, the last detected pallet pose: the region of interest is centred on it
  /// instead of on `pallet` [Stacker thesis, section 6.2.1]; the docking area stays on `pallet`.
  std::optional<geometry::Pose2> roi_centre;
};

struct PalletDetectorParams {
  PalletFaceModel pallet;
  double roi_margin = 0.15;  ///< metres added around the docking area before projecting it
  /// Heights above the pallet's base scanned for the pockets, bottom to top. Below 3 cm a ray
  /// through a pocket meets the floor too close behind the face to tell it from a block; above
  /// 9.5 cm the cross board begins (at 10 cm).
  double scan_bottom = 0.030;
  double scan_top = 0.095;
  int scan_slices = 3;             ///< overlapping height slices between scan_bottom and scan_top
  double face_band = 0.035;        ///< a return this close (along its ray) to the face counts as face, metres
  double width_tolerance = 0.035;  ///< column and pocket widths may differ this much (plus one bin), metres
  double min_run = 0.04;           ///< narrower runs in a slice are noise, metres
  double fit_inlier = 0.03;        ///< face points this close to the fitted face line are inliers, metres
  int min_face_points = 30;
};

/// The result of one frame. Positions and yaw are in the robot frame.
struct Detection {
  bool found = false;
  /// The centre of the middle block's front face [Stacker thesis, section 5.4: the midpoint].
  geometry::Vec2 midpoint;
  /// Pallet yaw: the direction out of the seen face, towards the camera.
  double yaw = 0.0;
  int features = 0;               ///< edges matched, of the six of two pockets and three columns
  int slices = 0;                 ///< height slices in which all six matched
  int face_points = 0;            ///< depth points of the least-squares face fit
  std::array<double, 6> edges{};  ///< matched edges along the face, metres from the midpoint
  std::string reason;             ///< why not found; empty when found

  /// The pallet footprint centre with `yaw`, half a pallet length behind the midpoint.
  geometry::Pose2 pallet_pose(double length = 1.2) const;
};

/// Finds the pallet in one depth image [Stacker thesis, sections 5.4 and 6.2]: projects the
/// docking area into the image as the region of interest, fits the face line by least squares
/// through the depth points of the face (beyond the thesis, whose yaw estimate its author calls
/// poor), segments each pixel as face / not face by where its ray crosses that line, scans
/// height slices bottom to top and the face left to right for the 0-1 transitions, matches them
/// against the column and pocket widths until six features match, and returns the midpoint.
Detection detect_pallet(const DepthImage& image, const DepthCameraModel& camera, const PalletExpectation& expected,
                        const PalletDetectorParams& params = {});

/// The pixels detect_pallet reads for `expected`: the region of interest [Stacker thesis,
/// section 6.2.1]. A camera need render nothing else.
PixelWindow detection_window(const DepthCameraModel& camera, const PalletExpectation& expected,
                             const PalletDetectorParams& params = {});

/// Follows one pallet from frame to frame: each frame's region of interest is centred on the
/// last detection [Stacker thesis, section 6.2.1], while the docking area stays on the target.
/// Loses the track after `max_misses` frames in a row without a detection.
class PalletTracker {
 public:
  explicit PalletTracker(DepthCameraModel camera, PalletDetectorParams params = {}, int max_misses = 3);

  /// The pallet to look for, in the map frame (from logistics).
  void set_target(const geometry::Pose2& pallet_in_map, double base_height, DockingArea area = {});
  /// Processes one frame taken with the robot at `robot_in_map`; the detection is in the robot frame.
  Detection update(const DepthImage& image, const geometry::Pose2& robot_in_map);

  bool tracking() const { return last_in_map_.has_value(); }
  /// The last detected pallet pose (footprint centre) in the map frame.
  const std::optional<geometry::Pose2>& last_in_map() const { return last_in_map_; }

 private:
  DepthCameraModel camera_;
  PalletDetectorParams params_;
  int max_misses_;
  geometry::Pose2 target_;
  double base_height_ = 0.0;
  DockingArea area_;
  std::optional<geometry::Pose2> last_in_map_;
  int misses_ = 0;
};

}  // namespace fleet::perception
