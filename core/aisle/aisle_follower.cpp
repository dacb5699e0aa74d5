#include "aisle/aisle_follower.hpp"

#include <cmath>
#include <stdexcept>

namespace fleet::aisle {

namespace {

/// One step of the discretised first-order lag of [Picker thesis, eq. 4.26]: x_n = τ/(T+τ)·x_{n−1} + T/(T+τ)·target,
/// with the static gain k = 1 because the commands are already in m/s and rad/s [Picker thesis, section 4.3.3.4].
double first_order(double previous, double target, double tau, double dt) {
  return tau / (dt + tau) * previous + dt / (dt + tau) * target;
}

}  // namespace

std::string_view to_string(RackSide side) {
  return side == RackSide::kLeft ? "left" : "right";
}

std::string_view to_string(AisleErrorStatus status) {
  switch (status) {
    case AisleErrorStatus::kValid:
      return "valid";
    case AisleErrorStatus::kNoRackLines:
      return "no rack lines";
    case AisleErrorStatus::kHeadingOutside:
      return "heading error beyond its limit";
    case AisleErrorStatus::kLateralOutside:
      return "lateral error beyond its limit";
  }
  return "unknown";
}

double sigmoid(double z, double lambda) {
  // (1 − e^(−λz)) / (1 + e^(−λz)) is tanh(λz/2), which does not overflow for large |λz|.
  return std::tanh(0.5 * lambda * z);
}

AisleErrors aisle_errors(const RackLinePair& pair, double distance_to_go, const AisleFollowerParams& params) {
  AisleErrors e;
  e.along = distance_to_go;
  if (!pair.found()) return e;
  // [Picker thesis, eq. 4.24]: e_θ = θ_line − θ_ref with θ_ref = 0, the base parallel to the racks.
  e.heading = pair.heading;
  // [Picker thesis, eq. 4.24] writes e_y = d_ref − (X_m,line − W_rack/2), a distance taken through the aisle centre in
  // range-image pixels. Measured here straight from the chosen face's line, so that an aisle wider or narrower than
  // W_rack does not move the picker off d_ref; the sign makes e_y the body-y displacement that brings the base to
  // d_ref.
  const HoughLine& face = params.side == RackSide::kRight ? pair.right : pair.left;
  e.side_distance = std::abs(face.rho);
  e.lateral = params.side == RackSide::kRight ? params.reference_distance - e.side_distance
                                              : e.side_distance - params.reference_distance;
  // Validity limits [Picker thesis, section 4.3.3.4]: |e_θ| ≤ π/3 and |e_y| ≤ w_R / cos(e_θ).
  if (std::abs(e.heading) > params.max_heading_error) {
    e.status = AisleErrorStatus::kHeadingOutside;
  } else if (std::abs(e.lateral) > params.rack_width / std::cos(e.heading)) {
    e.status = AisleErrorStatus::kLateralOutside;
  } else {
    e.status = AisleErrorStatus::kValid;
  }
  return e;
}

AisleFollower::AisleFollower(const AisleFollowerParams& params) : params_(params) {
  if (!(params.reference_distance > 0.0) || !(params.rack_width > params.reference_distance) ||
      !(params.max_heading_error > 0.0) || !(params.max_heading_error < std::numbers::pi / 2.0)) {
    throw std::invalid_argument(
        "AisleFollowerParams: 0 < reference_distance < rack_width, 0 < max_heading_error < pi/2");
  }
  if (!(params.forward_speed > 0.0) || !(params.lateral_speed > 0.0) || !(params.yaw_rate > 0.0) ||
      !(params.lambda_x > 0.0) || !(params.lambda_y > 0.0) || !(params.lambda_theta > 0.0) || !(params.tau_u >= 0.0) ||
      !(params.tau_v >= 0.0) || !(params.tau_r >= 0.0)) {
    throw std::invalid_argument("AisleFollowerParams: speeds and slopes > 0, time constants >= 0");
  }
}

void AisleFollower::start(double distance) {
  distance_ = distance;
  travelled_ = 0.0;
  heading_ = 0.0;
  command_ = {};
  errors_ = {};
}

sim::BodyTwist AisleFollower::update(const RackLinePair& pair, const sim::BodyTwist& odometry, double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) return command_;
  // X_R of [Picker thesis, eq. 4.24]: the lines give no position along the aisle, so the wheel odometry of the last
  // period is projected on the aisle's direction (cos e_θ, sin e_θ) in the body frame.
  travelled_ += (odometry.vx * std::cos(heading_) + odometry.vy * std::sin(heading_)) * dt;
  errors_ = aisle_errors(pair, distance_to_go(), params_);

  sim::BodyTwist target;
  if (errors_.valid()) {
    heading_ = errors_.heading;
    const double c = std::cos(errors_.heading);
    // [Picker thesis, eq. 4.33]: (1 − |e_y/w_R|) as in 4.33; eq. 4.30 prints y_A (an axis, not a length) in its place
    // and puts cos(e_θ) inside the bracket.
    target.vx = params_.forward_speed * sigmoid(errors_.along, params_.lambda_x) *
                (1.0 - std::abs(errors_.lateral / params_.rack_width)) * c;
    target.vy = params_.lateral_speed * sigmoid(errors_.lateral, params_.lambda_y) * c;  // [Picker thesis, eq. 4.34]
    target.omega = params_.yaw_rate * sigmoid(errors_.heading, params_.lambda_theta);    // [Picker thesis, eq. 4.35]
  }
  command_.vx = first_order(command_.vx, target.vx, params_.tau_u, dt);
  command_.vy = first_order(command_.vy, target.vy, params_.tau_v, dt);
  command_.omega = first_order(command_.omega, target.omega, params_.tau_r, dt);
  return command_;
}

}  // namespace fleet::aisle
