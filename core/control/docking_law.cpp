#include "control/docking_law.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fleet::control {

namespace {

using P = DockingPhase;
using E = DockingEvent;
using geometry::Vec2;

constexpr std::array kTable = {
    // The two-target approach [Stacker thesis, section 6.3.2].
    DockingTransition{P::kToTarget1, E::kNearTarget1, P::kReverseToTarget2},
    DockingTransition{P::kReverseToTarget2, E::kTarget2Reached, P::kPivot},
    // Pivot about the rear axle until the rear faces the pallet [Stacker thesis, section 5.2, 6.3].
    DockingTransition{P::kPivot, E::kPivotDone, P::kFinalApproach},
    // The final law: beyond the threshold by eq. 6.5 at -0.25 m/s, inside it in place by eq. 6.4 [Stacker thesis,
    // section 6.3.3].
    DockingTransition{P::kFinalApproach, E::kThresholdAligned, P::kFinalAlign},
    DockingTransition{P::kFinalAlign, E::kAligned, P::kForkIn},
    DockingTransition{P::kForkIn, E::kForksIn, P::kDone},
    // Beyond the thesis: out along the pallet axis and in again when the fork tips miss the pockets.
    DockingTransition{P::kFinalApproach, E::kThresholdMisaligned, P::kRealign},
    DockingTransition{P::kRealign, E::kRealigned, P::kFinalApproach},
    DockingTransition{P::kFinalApproach, E::kGiveUp, P::kFailed},
};

bool finite(const geometry::Pose2& p) {
  return geometry::is_finite(p);
}

double sign_of(double x) {
  return x < 0.0 ? -1.0 : 1.0;
}

/// Speed that falls linearly from `cruise` to `slow` over the last `ramp` metres before `remaining` reaches 0.
double ramped_speed(double remaining, double ramp, double cruise, double slow) {
  if (ramp <= 0.0 || remaining >= ramp) return cruise;
  return slow + (cruise - slow) * std::max(0.0, remaining) / ramp;
}

}  // namespace

const char* to_string(DockingPhase phase) {
  switch (phase) {
    case P::kToTarget1:
      return "to_target1";
    case P::kReverseToTarget2:
      return "reverse_to_target2";
    case P::kPivot:
      return "pivot";
    case P::kFinalApproach:
      return "final_approach";
    case P::kFinalAlign:
      return "final_align";
    case P::kRealign:
      return "realign";
    case P::kForkIn:
      return "fork_in";
    case P::kDone:
      return "done";
    case P::kFailed:
      return "failed";
  }
  return "unknown";
}

const char* to_string(DockingEvent event) {
  switch (event) {
    case E::kNearTarget1:
      return "near_target1";
    case E::kTarget2Reached:
      return "target2_reached";
    case E::kPivotDone:
      return "pivot_done";
    case E::kThresholdAligned:
      return "threshold_aligned";
    case E::kThresholdMisaligned:
      return "threshold_misaligned";
    case E::kRealigned:
      return "realigned";
    case E::kAligned:
      return "aligned";
    case E::kForksIn:
      return "forks_in";
    case E::kGiveUp:
      return "give_up";
    case E::kTimeout:
      return "timeout";
    case E::kBadInput:
      return "bad_input";
  }
  return "unknown";
}

std::span<const DockingTransition> docking_transition_table() {
  return kTable;
}

std::optional<DockingPhase> next_docking_phase(DockingPhase from, DockingEvent event) {
  if (from == P::kDone || from == P::kFailed) return std::nullopt;
  if (event == E::kTimeout || event == E::kBadInput) return P::kFailed;
  for (const DockingTransition& row : kTable) {
    if (row.from == from && row.event == event) return row.to;
  }
  return std::nullopt;
}

/// The rear-axle midpoint in the pallet's entry-axis frame: s out of the face along the axis, l to the axis's left,
/// psi the yaw relative to the pallet's.
struct DockingLaw::AxisFrame {
  Vec2 axis;    ///< unit, out of the entry face
  Vec2 normal;  ///< unit, to the axis's left
  Vec2 face;    ///< entry-face midpoint
  double s = 0.0;
  double l = 0.0;
  double psi = 0.0;
  double tip_lateral = 0.0;  ///< fork-tip midpoint off the axis
  double tip_depth = 0.0;    ///< fork-tip midpoint beyond the face, into the pallet
};

DockingLaw::DockingLaw(const DockingParams& params, const geometry::Pose2& pallet_prior, const geometry::Pose2& start,
                       std::uint64_t seed)
    : params_(params),
      prior_(pallet_prior),
      logistics_prior_(pallet_prior),
      start_(start),
      navigator_(params.attractor, params.vehicle, seed) {
  if (!finite(pallet_prior) || !finite(start)) {
    throw std::invalid_argument("DockingLaw: pallet prior and start pose must be finite");
  }
  if (!(params_.target2_tolerance > 0.0) || !(params_.lookahead > 0.0) || !(params_.k2 > 0.0) || !(params_.k1 > 0.0) ||
      !(params_.final_speed > 0.0) || !(params_.pocket_depth > 0.0)) {
    throw std::invalid_argument("DockingParams: target2_tolerance, lookahead, k1, k2, final_speed, pocket_depth > 0");
  }
  // Target 1 lies beyond target 2 as seen from the start, so that the stacker drives past the pallet forwards and
  // reverses back to target 2 still parallel to the row [Stacker thesis, section 6.3.1: "depending on the starting
  // position"]. Right in front of the pallet, the heading decides.
  const Vec2 row{-std::sin(prior_.yaw), std::cos(prior_.yaw)};
  const double along = geometry::dot(start.position() - prior_.position(), row);
  const double heading = geometry::dot({std::cos(start.yaw), std::sin(start.yaw)}, row);
  side_ = std::abs(along) > 0.5 ? -sign_of(along) : sign_of(heading);
  navigator_.reset_speed(params_.approach_speed);
}

geometry::Pose2 DockingLaw::pallet_estimate() const {
  if (detections_ == 0) return prior_;
  return {sum_x_ / detections_, sum_y_ / detections_, std::atan2(sum_sin_, sum_cos_)};
}

void DockingLaw::correct_prior_heading(const geometry::Pose2& detection) {
  // Beyond the thesis: the pallets of a row stand square to its limiter, so a detection's yaw, any pallet's, measures
  // how far the frame the law steers in is turned against the map the logistics position is given in (the pose
  // sensor's heading error when docking started). The logistics position is turned by the mean of these offsets
  // about where the stacker started. A large offset is not a heading error but a pallet standing askew.
  const double offset = geometry::angle_diff(detection.yaw, logistics_prior_.yaw);
  if (std::abs(offset) > params_.max_heading_correction) return;
  heading_offsets_ += offset;
  ++heading_samples_;
  // Until several frames have measured it, the region searched stays where logistics put the pallet.
  if (heading_samples_ < params_.heading_samples) return;
  const double turn = heading_offsets_ / heading_samples_;
  const Vec2 from_start = logistics_prior_.position() - start_.position();
  const Vec2 turned{std::cos(turn) * from_start.x - std::sin(turn) * from_start.y,
                    std::sin(turn) * from_start.x + std::cos(turn) * from_start.y};
  prior_ = {start_.x + turned.x, start_.y + turned.y, geometry::normalize_angle(logistics_prior_.yaw + turn)};
}

void DockingLaw::accept_detection(const geometry::Pose2& detection) {
  if (detections_ == 0) {
    correct_prior_heading(detection);
    // The first is taken once the heading is measured by several frames: one frame's yaw is noisy.
    if (heading_samples_ < params_.heading_samples) return;
  }
  const geometry::Pose2 expected = pallet_estimate();
  const double gate = detections_ == 0 ? params_.detection_gate : params_.outlier_gate;
  if (geometry::distance(detection.position(), expected.position()) > gate) return;
  if (detections_ > 0 && std::abs(geometry::angle_diff(detection.yaw, expected.yaw)) > 0.2) return;
  // The pallet stands still in the frame the law steers in (the thesis's exact pose [Stacker thesis, section 8.1], or
  // odometry anchored once by an imperfect pose sensor), so the running mean of the detections in that frame is the
  // estimate; it averages the detector's noise down (the thesis calls its yaw poor).
  ++detections_;
  sum_x_ += detection.x;
  sum_y_ += detection.y;
  sum_cos_ += std::cos(detection.yaw);
  sum_sin_ += std::sin(detection.yaw);
}

DockingLaw::AxisFrame DockingLaw::axis_frame(const geometry::Pose2& vehicle) const {
  const geometry::Pose2 pallet = pallet_estimate();
  AxisFrame a;
  a.axis = {std::cos(pallet.yaw), std::sin(pallet.yaw)};
  a.normal = {-a.axis.y, a.axis.x};
  a.face = pallet.position() + 0.5 * params_.pallet.depth * a.axis;
  const Vec2 d = vehicle.position() - a.face;
  a.s = geometry::dot(d, a.axis);
  a.l = geometry::dot(d, a.normal);
  a.psi = geometry::angle_diff(vehicle.yaw, pallet.yaw);
  const Vec2 tip = sim::fork_tip_midpoint(vehicle, params_.vehicle) - a.face;
  a.tip_lateral = geometry::dot(tip, a.normal);
  a.tip_depth = -geometry::dot(tip, a.axis);
  return a;
}

std::array<Vec2, 2> DockingLaw::targets() const {
  const AxisFrame a = axis_frame(start_);
  const Vec2 target2 = a.face + params_.target2_standoff * a.axis;  // [Stacker thesis, eq. 6.1-6.2]
  return {target2 + side_ * params_.target1_offset * a.normal + params_.target1_extra_standoff * a.axis, target2};
}

void DockingLaw::fire(DockingEvent event, DockingOutput& out) {
  const std::optional<DockingPhase> next = next_docking_phase(phase_, event);
  if (!next) return;
  phase_ = *next;
  out.event = event;
  steer_settled_ = false;
  confirmations_ = 0;
  if (phase_ == P::kReverseToTarget2) navigator_.reset_speed(params_.reverse_speed);
}

double DockingLaw::after_steering_settles(double theta, double measured, double v) {
  if (!steer_settled_ && std::abs(theta - measured) < params_.steer_settle_tolerance) steer_settled_ = true;
  return steer_settled_ ? v : 0.0;
}

DockingOutput DockingLaw::update(const DockingInput& in) {
  DockingOutput out;
  out.phase = phase_;
  out.failure_reason = failure_;
  if (phase_ == P::kDone || phase_ == P::kFailed) {
    out.command = {0.0, in.steer_angle};
    out.pallet_estimate = pallet_estimate();
    return out;
  }
  if (!finite(in.vehicle) || !std::isfinite(in.dt) || in.dt <= 0.0 || !std::isfinite(in.steer_angle)) {
    failure_ = "non-finite vehicle pose, steering angle or time step";
    fire(E::kBadInput, out);
  } else {
    elapsed_ += in.dt;
    if (elapsed_ > params_.time_limit) {
      failure_ = std::string("time limit exceeded in ") + to_string(phase_);
      fire(E::kTimeout, out);
    }
  }
  if (in.pallet_detection && finite(*in.pallet_detection)) accept_detection(*in.pallet_detection);

  const geometry::Pose2 pallet = pallet_estimate();
  const AxisFrame a = axis_frame(in.vehicle);
  out.pallet_estimate = pallet;
  const auto [target1, target2] = targets();
  out.target1 = target1;
  out.target2 = target2;
  out.lateral_error = a.tip_lateral;
  out.yaw_error = a.psi;

  const DockingPhase before = phase_;
  sim::TricycleCommand cmd{0.0, in.steer_angle};
  switch (phase_) {
    case P::kToTarget1:
      cmd = to_target1(in, out);
      break;
    case P::kReverseToTarget2:
      cmd = reverse_to_target2(in, out);
      break;
    case P::kPivot:
      cmd = pivot(in, out);
      break;
    case P::kFinalApproach:
      cmd = final_approach(in, out);
      break;
    case P::kFinalAlign:
      cmd = final_align(in, out);
      break;
    case P::kRealign:
      cmd = realign(in, out);
      break;
    case P::kForkIn:
      cmd = fork_in(in, out);
      break;
    case P::kDone:
    case P::kFailed:
      break;
  }
  // A phase that just ended stands still for one period; the next one starts from the next update.
  if (phase_ != before) cmd = {0.0, in.steer_angle};
  out.command = cmd;
  out.phase = phase_;
  out.failure_reason = failure_;
  return out;
}

sim::TricycleCommand DockingLaw::to_target1(const DockingInput& in, DockingOutput& out) {
  const AttractorOutput nav =
      navigator_.update(in.vehicle, {out.target1, 1, params_.approach_speed}, in.obstacles, in.dt);
  if (nav.target_distance < params_.target1_switch_distance) fire(E::kNearTarget1, out);
  return nav.command;
}

sim::TricycleCommand DockingLaw::reverse_to_target2(const DockingInput& in, DockingOutput& out) {
  const double distance = geometry::distance(in.vehicle.position(), out.target2);
  // Beyond the thesis: v_des falls with the distance so that the 0.05 m arrival is met without overshoot.
  const double v_des = std::clamp(params_.arrival_gain * distance, params_.min_arrival_speed, params_.reverse_speed);
  const AttractorOutput nav = navigator_.update(in.vehicle, {out.target2, -1, v_des}, in.obstacles, in.dt);
  if (distance < params_.target2_tolerance) fire(E::kTarget2Reached, out);
  return nav.command;
}

sim::TricycleCommand DockingLaw::pivot(const DockingInput& in, DockingOutput& out) {
  const double error = geometry::angle_diff(out.pallet_estimate.yaw, in.vehicle.yaw);
  if (!steer_settled_) turn_sign_ = sign_of(error);
  if (std::abs(error) < params_.pivot_tolerance) {
    fire(E::kPivotDone, out);
    return {0.0, in.steer_angle};
  }
  // theta_steer = +-pi/2 puts the ICR on the rear-axle midpoint [Stacker thesis, eq. 5.2];
  // phi' = v_steer sin(theta) / L.
  const double theta = turn_sign_ * std::numbers::pi / 2.0;
  const double v = std::clamp(params_.pivot_gain * error * params_.vehicle.wheelbase * turn_sign_,
                              -params_.max_pivot_wheel_speed, params_.max_pivot_wheel_speed);
  return {after_steering_settles(theta, in.steer_angle, v), theta};
}

sim::TricycleCommand DockingLaw::final_approach(const DockingInput& in, DockingOutput& out) {
  const AxisFrame a = axis_frame(in.vehicle);
  if (a.s <= params_.threshold_standoff) {
    if (detections_ == 0 && !params_.place_on_prior) {
      // Never seen where logistics put it: fork nothing in blind [Stacker thesis, section 6.3].
      failure_ = "pallet not found: no detection inside the expected docking area";
      fire(E::kGiveUp, out);
      return {0.0, in.steer_angle};
    }
    const bool on_pockets =
        std::abs(a.tip_lateral) <= params_.lateral_tolerance && std::abs(a.psi) <= params_.entry_yaw_tolerance;
    if (on_pockets) {
      fire(E::kThresholdAligned, out);
    } else if (realignments_ >= params_.max_realignments) {
      failure_ = "fork tips off the pockets after " + std::to_string(realignments_) + " realignments";
      fire(E::kGiveUp, out);
    } else {
      ++realignments_;
      fire(E::kThresholdMisaligned, out);
    }
    return {0.0, in.steer_angle};
  }
  // [Stacker thesis, eq. 6.3] e = sigma - theta. theta: bearing of the pallet midpoint in the rear camera's image
  // (positive to the image's right). sigma: the bearing it would have if the rear pointed at the pallet axis
  // `lookahead` ahead, so that the lateral offset decays along the way instead of the stacker arriving at the midpoint
  // askew (the thesis aims at the midpoint itself, sigma fixed). The thesis's |theta| loses the side; the sign is kept
  // here.
  const Vec2 midpoint = geometry::map_to_body(in.vehicle, a.face);
  const double theta = std::atan2(midpoint.y, -midpoint.x);
  const double psi_wanted = std::atan(a.l / params_.lookahead);
  const double sigma = theta + geometry::angle_diff(psi_wanted, a.psi);
  const double e = sigma - theta;
  out.final_error = e;
  // [Stacker thesis, eq. 6.5] theta_steer = -K2 e at the thesis's constant -0.25 m/s, slowing for the last metres
  // (beyond the thesis).
  const double steer = std::clamp(-params_.k2 * e, -params_.max_final_steer, params_.max_final_steer);
  const double speed = ramped_speed(a.s - params_.threshold_standoff, params_.final_slow_distance, params_.final_speed,
                                    params_.final_slow_speed);
  return {after_steering_settles(steer, in.steer_angle, -speed), steer};
}

sim::TricycleCommand DockingLaw::final_align(const DockingInput& in, DockingOutput& out) {
  // Inside the threshold [Stacker thesis, section 6.3.3]: theta_steer = +-pi/2 by the sign of e, v_steer = K1 e
  // [Stacker thesis, eq. 6.4]; with the rear on the axis, e is the orientation error to the pallet. The side is chosen
  // once, so an overshoot is corrected by the wheel's direction rather than a half turn of the steering.
  const double e = geometry::angle_diff(out.pallet_estimate.yaw, in.vehicle.yaw);
  out.final_error = e;
  if (!steer_settled_) {
    if (std::abs(e) < params_.align_tolerance) {
      fire(E::kAligned, out);
      return {0.0, in.steer_angle};
    }
    turn_sign_ = sign_of(e);
  }
  if (std::abs(e) < params_.align_tolerance) {
    if (++confirmations_ >= params_.align_confirmations) {
      fire(E::kAligned, out);
      return {0.0, in.steer_angle};
    }
  } else {
    confirmations_ = 0;
  }
  const double theta = turn_sign_ * std::numbers::pi / 2.0;
  const double v = std::clamp(params_.k1 * e * turn_sign_, -0.1, 0.1);
  return {after_steering_settles(theta, in.steer_angle, v), theta};
}

sim::TricycleCommand DockingLaw::realign(const DockingInput& in, DockingOutput& out) {
  // Forwards out along the pallet axis, pursuing it `lookahead` ahead: the same law as eq. 6.5 mirrored.
  const AxisFrame a = axis_frame(in.vehicle);
  if (a.s >= params_.realign_standoff) {
    fire(E::kRealigned, out);
    return {0.0, in.steer_angle};
  }
  const double e = geometry::angle_diff(std::atan(-a.l / params_.lookahead), a.psi);
  const double steer = std::clamp(params_.k2 * e, -params_.max_final_steer, params_.max_final_steer);
  const double speed =
      ramped_speed(params_.realign_standoff - a.s, 0.15, params_.realign_speed, params_.final_slow_speed);
  return {after_steering_settles(steer, in.steer_angle, speed), steer};
}

sim::TricycleCommand DockingLaw::fork_in(const DockingInput& in, DockingOutput& out) {
  // Straight in, in reverse, until the fork tips are at the pocket depth [Stacker thesis, section 6.3.3 "fork the
  // pallet"]; "straight" holds the yaw on the pallet's, which a steering offset or lag would otherwise turn.
  const AxisFrame a = axis_frame(in.vehicle);
  const double remaining = params_.pocket_depth - a.tip_depth;
  if (remaining <= 0.002) {
    fire(E::kForksIn, out);
    return {0.0, in.steer_angle};
  }
  const double speed = ramped_speed(remaining, 0.15, params_.fork_in_speed, 0.03);
  const double e = geometry::angle_diff(out.pallet_estimate.yaw, in.vehicle.yaw);
  // phi' = v sin(theta) / L = gain e with v = -speed.
  const double s = std::clamp(params_.yaw_hold_gain * e * params_.vehicle.wheelbase / -speed,
                              -std::sin(params_.max_fork_in_steer), std::sin(params_.max_fork_in_steer));
  const double steer = std::asin(s);
  return {after_steering_settles(steer, in.steer_angle, -speed), steer};
}

}  // namespace fleet::control
