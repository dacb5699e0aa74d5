#include "control/pallet_pick.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::control {

const char* to_string(PickStatus status) {
  switch (status) {
    case PickStatus::kIdle:
      return "idle";
    case PickStatus::kAligning:
      return "aligning";
    case PickStatus::kDrivingIn:
      return "driving_in";
    case PickStatus::kLifting:
      return "lifting";
    case PickStatus::kDone:
      return "done";
    case PickStatus::kFailed:
      return "failed";
  }
  return "unknown";
}

PalletPick::PalletPick(PickParams params, ForkliftGeometry geometry) : params_(params), geometry_(geometry) {}

void PalletPick::start(int marker_id, double t) {
  marker_id_ = marker_id;
  status_ = PickStatus::kAligning;
  start_time_ = t;
  last_seen_ = t;
  phase_start_ = t;
  settled_ = 0;
  d_sum_ = 0.0;
  held_ = {};
  failure_ = "";
}

void PalletPick::stop() {
  status_ = PickStatus::kIdle;
  held_ = {};
}

BodyTwist PalletPick::servo_command(const perception::MarkerDetection& det, const PickParams& p, bool& aligned) {
  // One error at a time, in the order alpha, gamma, d [Forklift thesis, eq. 6.4 and Fig. 6.7].
  BodyTwist cmd;
  aligned = false;
  const double dd = det.d - p.d_min;
  if (std::abs(det.alpha) > p.alpha_min) {
    cmd.vy = std::copysign(p.v_miny, det.alpha);  // v_y = v_miny * alpha / |alpha|
  } else if (std::abs(det.gamma) > p.gamma_min) {
    // omega = omega_min * gamma / |gamma_min|: proportional, capped so a large gamma cannot spin
    // the marker out of view.
    cmd.omega = std::clamp(p.omega_min * det.gamma / std::abs(p.gamma_min), -p.omega_limit, p.omega_limit);
  } else if (std::abs(dd) > p.d_tol) {
    cmd.vx = std::copysign(p.v_minx, dd);  // v_x = v_minx * (d - d_min) / |d - d_min|
  } else {
    aligned = true;
  }
  return cmd;
}

ForkCommand PalletPick::step(double t, std::span<const perception::MarkerDetection> detections, double dt) {
  ForkCommand out;
  if (status_ == PickStatus::kIdle || done()) {
    out.fork_up = status_ == PickStatus::kDone;
    return out;
  }
  if (t - start_time_ > params_.timeout) {
    status_ = PickStatus::kFailed;
    failure_ = "pick timed out";
    return out;
  }
  if (status_ == PickStatus::kAligning) {
    const perception::MarkerDetection* det = nullptr;
    for (const auto& d : detections) {
      if (d.id == marker_id_) det = &d;
    }
    if (det == nullptr) {
      if (t - last_seen_ > params_.lost_timeout) {
        status_ = PickStatus::kFailed;
        failure_ = "marker lost while aligning";
        return out;
      }
      // Between frames the last command stands; a longer gap stops the robot rather than let it
      // drive on stale information.
      if (t - last_seen_ <= params_.hold_time) out.twist = held_;
      return out;
    }
    last_seen_ = t;
    bool aligned = false;
    held_ = servo_command(*det, params_, aligned);
    if (!aligned) {
      settled_ = 0;
      d_sum_ = 0.0;
      out.twist = held_;
      return out;
    }
    ++settled_;
    d_sum_ += det->d;
    if (settled_ < params_.settle_frames) return out;
    // Aligned: drive straight in until the marker is where it sits when the pallet is on the forks.
    drive_left_ = d_sum_ / settled_ - geometry_.carried_marker_distance();
    status_ = PickStatus::kDrivingIn;
    phase_start_ = t;
    held_ = {};
  }
  if (status_ == PickStatus::kDrivingIn) {
    // Blind: distance from the commanded speed, since the marker is too close to decode.
    if (drive_left_ > 1e-4) {
      const double v = std::min(params_.drive_in_speed, drive_left_ / std::max(dt, 1e-3));
      out.twist.vx = v;
      drive_left_ -= v * std::max(dt, 0.0);
      return out;
    }
    status_ = PickStatus::kLifting;
    phase_start_ = t;
  }
  if (status_ == PickStatus::kLifting) {
    out.fork_up = true;
    if (t - phase_start_ >= params_.lift_time) status_ = PickStatus::kDone;
  }
  return out;
}

}  // namespace fleet::control
