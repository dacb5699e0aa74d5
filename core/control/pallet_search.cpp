#include "control/pallet_search.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace fleet::control {

using geometry::angle_diff;
using geometry::normalize_angle;
using geometry::Pose2;

const char* to_string(SearchStatus status) {
  switch (status) {
    case SearchStatus::kIdle:
      return "idle";
    case SearchStatus::kApproaching:
      return "approaching";
    case SearchStatus::kSweeping:
      return "sweeping";
    case SearchStatus::kFound:
      return "found";
    case SearchStatus::kEmpty:
      return "empty";
  }
  return "unknown";
}

PalletSearch::PalletSearch(SearchParams params, ForkliftGeometry geometry)
    : params_(params), geometry_(geometry), follower_(params.approach) {}

Pose2 PalletSearch::search_pose(const Pose2& area, double standoff) {
  // LoadingArea::pose.yaw points from the pallet towards the approach side; the forklift stands
  // `standoff` out along it and faces back at the pallet.
  return {area.x + standoff * std::cos(area.yaw), area.y + standoff * std::sin(area.yaw),
          normalize_angle(area.yaw + std::numbers::pi)};
}

void PalletSearch::start(const Pose2& area) {
  area_ = area;
  look_pose_ = search_pose(area, params_.standoff);
  follower_.set_pose_target(look_pose_);
  status_ = SearchStatus::kApproaching;
  sweep_leg_ = 0;
  marker_id_ = -1;
  hits_ = 0;
  frames_seen_ = 0;
  nearest_rejected_id_ = -1;
  nearest_rejected_m_ = 0.0;
}

void PalletSearch::stop() {
  follower_.clear();
  status_ = SearchStatus::kIdle;
}

void PalletSearch::count(const Pose2& pose, std::span<const perception::MarkerDetection> detections) {
  const geometry::Vec2 expected =
      area_.position() + geometry_.marker_offset * geometry::Vec2{std::cos(area_.yaw), std::sin(area_.yaw)};
  for (const auto& det : detections) {
    const perception::Marker seen = perception::marker_from_detection(pose, geometry_.camera_x, det);
    ++frames_seen_;
    const double off = geometry::distance(seen.pose.position(), expected);
    if (off > params_.match_radius) {
      if (nearest_rejected_id_ < 0 || off < nearest_rejected_m_) {
        nearest_rejected_id_ = det.id;
        nearest_rejected_m_ = off;
      }
      continue;
    }
    if (det.id != marker_id_) {
      marker_id_ = det.id;
      hits_ = 0;
    }
    ++hits_;
  }
}

std::string PalletSearch::empty_reason() const {
  if (frames_seen_ == 0) return "no marker in view";
  char text[160];
  if (nearest_rejected_id_ < 0) {
    std::snprintf(text, sizeof text, "marker %d seen in %d frames, fewer than %d", marker_id_, hits_,
                  params_.confirm_frames);
  } else {
    std::snprintf(text, sizeof text, "nearest marker %d seen %.3f m from the pallet's place (accepted within %.2f m)",
                  nearest_rejected_id_, nearest_rejected_m_, params_.match_radius);
  }
  return text;
}

BodyTwist PalletSearch::step(const Pose2& pose, std::span<const perception::MarkerDetection> detections, double dt) {
  if (status_ == SearchStatus::kIdle || done()) return {};
  count(pose, detections);
  if (status_ == SearchStatus::kApproaching) {
    const BodyTwist cmd = follower_.step({pose, dt});
    if (!follower_.arrived()) return cmd;
    status_ = SearchStatus::kSweeping;
  }
  if (hits_ >= params_.confirm_frames) {
    status_ = SearchStatus::kFound;
    return {};
  }
  // Sweep: +half, then -half, then back to facing the pallet; nothing seen means empty.
  const double centre = look_pose_.yaw;
  const double goals[3] = {centre + params_.sweep_half_angle, centre - params_.sweep_half_angle, centre};
  while (sweep_leg_ < 3) {
    const double err = angle_diff(goals[sweep_leg_], pose.yaw);
    if (std::abs(err) > 0.02) {
      BodyTwist cmd;
      cmd.omega = std::copysign(params_.sweep_omega, err);
      return cmd;
    }
    ++sweep_leg_;
  }
  status_ = SearchStatus::kEmpty;
  return {};
}

}  // namespace fleet::control
