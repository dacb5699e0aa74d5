#pragma once

#include <span>
#include <string>

#include "control/forklift_geometry.hpp"
#include "control/path_follower.hpp"
#include "perception/marker_camera.hpp"

namespace fleet::control {

struct SearchParams {
  double standoff = 0.30;          ///< robot centre to pallet centre at the search pose, metres
  double sweep_half_angle = 0.70;  ///< turn this far either side of facing the pallet, rad
  double sweep_omega = 0.40;       ///< turning speed while sweeping, rad/s
  int confirm_frames = 3;          ///< detections of the same marker needed to call it found
  /// A marker counts only if it lies this close to where the order says the pallet is, metres;
  /// a neighbour's pallet or a sloppy earlier drop beyond this is not the one ordered.
  double match_radius = 0.10;
  FollowerParams approach = approach_defaults();  ///< pose-target mode to the search pose

  static FollowerParams approach_defaults() {
    FollowerParams p;
    p.v_max = 0.10;
    p.goal_tolerance = 0.015;
    p.heading_tolerance = 0.03;
    return p;
  }
};

enum class SearchStatus { kIdle, kApproaching, kSweeping, kFound, kEmpty };
const char* to_string(SearchStatus status);

/// Pallet search [Forklift thesis, section 6.1]: go to a local target in front of the pallet with the
/// follower's pose-target mode, then turn until the marker is in view. No marker after a full
/// sweep means the area is empty (Forklift thesis, section 6.4: the area is reported empty).
class PalletSearch {
 public:
  explicit PalletSearch(SearchParams params = {}, ForkliftGeometry geometry = {});

  /// The pose in front of a loading area from which the forklift looks at its pallet.
  static geometry::Pose2 search_pose(const geometry::Pose2& area, double standoff);

  /// Starts searching for the pallet the order places at `area` (loading-area pose).
  void start(const geometry::Pose2& area);
  void stop();

  /// One step with the pose estimate and the detections of any frame taken since the last step.
  BodyTwist step(const geometry::Pose2& pose, std::span<const perception::MarkerDetection> detections, double dt);

  SearchStatus status() const { return status_; }
  bool done() const { return status_ == SearchStatus::kFound || status_ == SearchStatus::kEmpty; }
  int marker_id() const { return marker_id_; }  ///< valid when found
  /// Why a sweep ended empty, for the operator: what the camera saw and how far from where the
  /// order puts the pallet ("no marker in view", or the nearest marker and its distance).
  std::string empty_reason() const;

 private:
  void count(const geometry::Pose2& pose, std::span<const perception::MarkerDetection> detections);

  SearchParams params_;
  ForkliftGeometry geometry_;
  PathFollower follower_;
  SearchStatus status_ = SearchStatus::kIdle;
  geometry::Pose2 area_;
  geometry::Pose2 look_pose_;
  int sweep_leg_ = 0;  ///< 0: towards +half, 1: towards -half, 2: back to centre
  int marker_id_ = -1;
  int hits_ = 0;
  int frames_seen_ = 0;           ///< detections counted since start, matched or not
  int nearest_rejected_id_ = -1;  ///< the marker seen nearest the expected place but outside match_radius
  double nearest_rejected_m_ = 0.0;
};

}  // namespace fleet::control
