#include "control/pallet_place.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fleet::control {

using geometry::angle_diff;
using geometry::Pose2;
using geometry::Vec2;

namespace {

/// Proportional command with a floor (below it the motors stall and the error would never close)
/// and a ceiling.
double shaped(double u, double floor, double limit, double error, double tol) {
  if (std::abs(error) <= tol) return 0.0;
  const double mag = std::clamp(std::abs(u), floor, limit);
  return std::copysign(mag, u);
}

}  // namespace

const char* to_string(PlaceStatus status) {
  switch (status) {
    case PlaceStatus::kIdle:
      return "idle";
    case PlaceStatus::kHeading:
      return "heading";
    case PlaceStatus::kLateral:
      return "lateral";
    case PlaceStatus::kLongitudinal:
      return "longitudinal";
    case PlaceStatus::kSettling:
      return "settling";
    case PlaceStatus::kLowering:
      return "lowering";
    case PlaceStatus::kBackingOut:
      return "backing_out";
    case PlaceStatus::kDone:
      return "done";
    case PlaceStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

PalletPlace::PalletPlace(PlaceParams params, ForkliftGeometry geometry) : params_(params), geometry_(geometry) {}

Pose2 PalletPlace::place_pose(const Pose2& area, double carry_x) {
  // The forklift faces the pallet (area yaw + pi) with the pallet centre carry_x ahead of it.
  return {area.x + carry_x * std::cos(area.yaw), area.y + carry_x * std::sin(area.yaw),
          geometry::normalize_angle(area.yaw + std::numbers::pi)};
}

void PalletPlace::start(const Pose2& area, double t) {
  target_ = place_pose(area, geometry_.carry_x);
  status_ = PlaceStatus::kHeading;
  start_time_ = t;
  phase_start_ = t;
  settles_ = 0;
}

void PalletPlace::stop() {
  status_ = PlaceStatus::kIdle;
}

ForkCommand PalletPlace::step(double t, const Pose2& pose, double dt) {
  ForkCommand out;
  out.fork_up = true;
  if (status_ == PlaceStatus::kIdle) return out;
  if (status_ == PlaceStatus::kDone || status_ == PlaceStatus::kFailed) {
    out.fork_up = status_ == PlaceStatus::kFailed;  // a failed place keeps the pallet
    return out;
  }
  if (t - start_time_ > params_.timeout && status_ <= PlaceStatus::kSettling) {
    status_ = PlaceStatus::kFailed;
    return out;
  }

  if (status_ <= PlaceStatus::kSettling) {
    // Errors of eq. 6.5. The position error is taken in the robot's own frame, so v_x and v_y
    // act on exactly the error they are meant to close even while a small heading error remains.
    const double dh = angle_diff(pose.yaw, target_.yaw);
    const Vec2 to_target = geometry::map_to_body(pose, target_.position());
    const double d_lat = -to_target.y;   // d_x of the thesis: sideways offset from the target line
    const double d_long = -to_target.x;  // d_y of the thesis: distance still to go, negated
    const bool h_ok = std::abs(dh) <= params_.heading_tol;
    const bool lat_ok = std::abs(d_lat) <= params_.lateral_tol;
    const bool long_ok = std::abs(d_long) <= params_.longitudinal_tol;

    if (status_ == PlaceStatus::kSettling) {
      if (t - phase_start_ < params_.settle_time) return out;  // stand still, let the estimate settle
      ++settles_;
      if ((h_ok && lat_ok && long_ok) || settles_ >= params_.max_settles) {
        status_ = PlaceStatus::kLowering;
        phase_start_ = t;
      } else {
        status_ = h_ok ? (lat_ok ? PlaceStatus::kLongitudinal : PlaceStatus::kLateral) : PlaceStatus::kHeading;
      }
    }
    if (status_ <= PlaceStatus::kLongitudinal) {
      if (status_ == PlaceStatus::kHeading && h_ok) status_ = PlaceStatus::kLateral;
      if (status_ == PlaceStatus::kLateral && lat_ok) status_ = PlaceStatus::kLongitudinal;
      if (status_ > PlaceStatus::kHeading && std::abs(dh) > params_.reenter_factor * params_.heading_tol) {
        status_ = PlaceStatus::kHeading;
      } else if (status_ > PlaceStatus::kLateral && std::abs(d_lat) > params_.reenter_factor * params_.lateral_tol) {
        status_ = PlaceStatus::kLateral;
      }
    }

    if (status_ == PlaceStatus::kLowering) {
      // Decided above, after settling: fall through to lowering.
    } else if (status_ == PlaceStatus::kLongitudinal && h_ok && lat_ok && long_ok) {
      status_ = params_.settle_time > 0.0 ? PlaceStatus::kSettling : PlaceStatus::kLowering;
      phase_start_ = t;
      if (status_ == PlaceStatus::kSettling) return out;
    } else {
      // omega = -a d_h, v_y = -b d_x, v_x = -c d_y [Forklift thesis, eq. 6.5]; each stage keeps the
      // earlier ones closed.
      out.twist.omega = shaped(-params_.a * dh, params_.omega_floor, params_.omega_limit, dh, params_.heading_tol);
      if (status_ >= PlaceStatus::kLateral) {
        out.twist.vy = shaped(-params_.b * d_lat, params_.v_floor, params_.vy_limit, d_lat, params_.lateral_tol);
      }
      if (status_ >= PlaceStatus::kLongitudinal) {
        out.twist.vx = shaped(-params_.c * d_long, params_.v_floor, params_.vx_limit, d_long, params_.longitudinal_tol);
      }
      return out;
    }
  }
  if (status_ == PlaceStatus::kLowering) {
    out.fork_up = false;
    if (t - phase_start_ < params_.lower_time) return out;
    status_ = PlaceStatus::kBackingOut;
    back_left_ = params_.back_out_distance;
  }
  if (status_ == PlaceStatus::kBackingOut) {
    out.fork_up = false;
    if (back_left_ > 1e-4) {
      const double v = std::min(params_.back_out_speed, back_left_ / std::max(dt, 1e-3));
      out.twist.vx = -v;
      back_left_ -= v * std::max(dt, 0.0);
      return out;
    }
    status_ = PlaceStatus::kDone;
  }
  return out;
}

}  // namespace fleet::control
