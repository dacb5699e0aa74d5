#include "localization/ekf.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace fleet::localization {

namespace {

constexpr double kPi = std::numbers::pi;

bool finite(const BodyVelocity& v) {
  return std::isfinite(v.vx) && std::isfinite(v.vy) && std::isfinite(v.omega);
}

void symmetrize(StateCovariance& p) {
  p = 0.5 * (p + p.transpose()).eval();
}

/// Linear Kalman update z = H x + v, v ~ N(0, diag(var)), on the whole state (Forklift thesis, eqs. 4.3-4.5).
template <int M>
void linear_update(StateVector& x, StateCovariance& p, const Eigen::Matrix<double, M, kStateSize>& h,
                   const Eigen::Matrix<double, M, 1>& z, const Eigen::Matrix<double, M, 1>& var) {
  const Eigen::Matrix<double, kStateSize, M> pht = p * h.transpose();
  Eigen::Matrix<double, M, M> s = h * pht;
  s.diagonal() += var;
  const Eigen::Matrix<double, kStateSize, M> k = pht * s.inverse();
  x += k * (z - h * x);
  p -= k * pht.transpose();
}

geometry::Vec2 rotate(double yaw, geometry::Vec2 v) {
  const double c = std::cos(yaw);
  const double s = std::sin(yaw);
  return {c * v.x - s * v.y, s * v.x + c * v.y};
}

}  // namespace

EkfParams EkfParams::seed() {
  return EkfParams{};
}

EkfParams EkfParams::tuned() {
  EkfParams p;
  // R_t per 70 Hz step. Position: only what the constant-velocity model misses within one step.
  // Heading: gyro white noise (5 mrad/s per sample) plus room to absorb its wandering bias.
  // Body velocities: the forklift's accelerations (about 0.3 m/s^2) over one step.
  p.process_noise = {1e-6, 1e-6, 2e-6, 2e-5, 2e-5, 1e-4};
  p.use_fix_covariance = true;
  p.uwb_std = 0.03;  // floor of Q_t; the solver's covariance is normally above it
  p.init_heading_std = 0.05;
  p.gating = true;
  p.velocity_source = VelocitySource::kCommanded;
  p.heading_init = true;
  p.gyro_bias = true;
  p.standstill_update = true;
  return p;
}

Ekf::Ekf(const EkfParams& params) : params_(params) {
  auto require = [](bool ok, const char* key, double value) {
    if (!ok) throw std::invalid_argument(std::string("EkfParams.") + key + " out of range: " + std::to_string(value));
  };
  for (double q : params_.process_noise) require(q >= 0.0 && std::isfinite(q), "process_noise", q);
  require(params_.nominal_dt > 0.0 && std::isfinite(params_.nominal_dt), "nominal_dt", params_.nominal_dt);
  require(params_.uwb_std > 0.0 && std::isfinite(params_.uwb_std), "uwb_std", params_.uwb_std);
  require(params_.init_position_std > 0.0, "init_position_std", params_.init_position_std);
  require(params_.init_heading_std > 0.0, "init_heading_std", params_.init_heading_std);
  require(params_.init_velocity_std > 0.0, "init_velocity_std", params_.init_velocity_std);
  require(params_.init_max_fix_std > 0.0, "init_max_fix_std", params_.init_max_fix_std);
  require(std::isfinite(params_.initial_heading), "initial_heading", params_.initial_heading);
  require(params_.gate_chi2 > 0.0, "gate_chi2", params_.gate_chi2);
  require(params_.max_consecutive_rejections >= 1, "max_consecutive_rejections", params_.max_consecutive_rejections);
  for (double s : params_.commanded_velocity_std) require(s > 0.0, "commanded_velocity_std", s);
  for (double s : params_.encoder_velocity_std) require(s > 0.0, "encoder_velocity_std", s);
  require(params_.heading_init_distance > 0.0, "heading_init_distance", params_.heading_init_distance);
  require(params_.gyro_bias_random_walk >= 0.0 && std::isfinite(params_.gyro_bias_random_walk), "gyro_bias_random_walk",
          params_.gyro_bias_random_walk);
  require(params_.init_gyro_bias_std > 0.0 && std::isfinite(params_.init_gyro_bias_std), "init_gyro_bias_std",
          params_.init_gyro_bias_std);
  require(params_.standstill_delay >= 0.0 && std::isfinite(params_.standstill_delay), "standstill_delay",
          params_.standstill_delay);
  for (double s : params_.standstill_velocity_std) {
    require(s > 0.0 && std::isfinite(s), "standstill_velocity_std", s);
  }
  require(params_.gyro_noise_std > 0.0 && std::isfinite(params_.gyro_noise_std), "gyro_noise_std",
          params_.gyro_noise_std);
}

StateVector Ekf::motion_model(const StateVector& x, double gyro_omega, double dt) {
  // Body velocities rotated into the map frame; heading from the gyro [Forklift thesis, eq. 4.8].
  // Beyond the thesis, the gyro reading is corrected by the bias state (b = 0 gives eq. 4.8 exactly); b
  // itself is a random walk, so its prediction is b.
  StateVector out = x;
  const double th = x(kTheta);
  out(kX) = x(kX) + x(kVx) * dt * std::cos(th) + x(kVy) * dt * std::cos(th + kPi / 2.0);
  out(kY) = x(kY) + x(kVx) * dt * std::sin(th) + x(kVy) * dt * std::sin(th + kPi / 2.0);
  out(kTheta) = th + (gyro_omega - x(kBias)) * dt;
  return out;
}

StateCovariance Ekf::motion_jacobian(const StateVector& x, double dt) {
  // [Forklift thesis, eq. 4.15]. The printed matrix also has dt at (theta, omega); that entry is the
  // derivative only if theta were propagated with the state's omega. Eq. 4.8 propagates it with
  // the gyro reading, an input, so the true derivative there is 0 and that is what is used here
  // (a Jacobian that disagrees with its model makes the filter over-confident about omega).
  const double th = x(kTheta);
  StateCovariance g = StateCovariance::Identity();
  g(kX, kTheta) = -dt * (std::sin(th) * x(kVx) + std::sin(th + kPi / 2.0) * x(kVy));
  g(kX, kVx) = std::cos(th) * dt;
  g(kX, kVy) = std::cos(th + kPi / 2.0) * dt;
  g(kY, kTheta) = dt * (std::cos(th) * x(kVx) + std::cos(th + kPi / 2.0) * x(kVy));
  g(kY, kVx) = std::sin(th) * dt;
  g(kY, kVy) = std::sin(th + kPi / 2.0) * dt;
  g(kTheta, kBias) = -dt;  // beyond the thesis: theta integrates (gyro - b)
  return g;
}

Eigen::Vector2d Ekf::measurement_model(const StateVector& x, const geometry::Vec2& offset) {
  // [Forklift thesis, eq. 4.13]
  const double th = x(kTheta);
  return {offset.x * std::cos(th) - offset.y * std::sin(th) + x(kX),
          offset.x * std::sin(th) + offset.y * std::cos(th) + x(kY)};
}

Eigen::Matrix<double, 2, kStateSize> Ekf::measurement_jacobian(const StateVector& x, const geometry::Vec2& offset) {
  // [Forklift thesis, eq. 4.17] (the printed matrix drops the omega column; it is zero, as is the bias's).
  const double th = x(kTheta);
  Eigen::Matrix<double, 2, kStateSize> h = Eigen::Matrix<double, 2, kStateSize>::Zero();
  h(0, kX) = 1.0;
  h(1, kY) = 1.0;
  h(0, kTheta) = -offset.x * std::sin(th) - offset.y * std::cos(th);
  h(1, kTheta) = offset.x * std::cos(th) - offset.y * std::sin(th);
  return h;
}

Eigen::Matrix2d Ekf::measurement_noise(const Eigen::Matrix2d& fix_covariance) const {
  Eigen::Matrix2d q = params_.uwb_std * params_.uwb_std * Eigen::Matrix2d::Identity();
  if (params_.use_fix_covariance) {
    // The solver's covariance, but never more confident than the floor in any direction.
    q += 0.5 * (fix_covariance + fix_covariance.transpose());
  }
  return q;
}

void Ekf::initialize(const geometry::Vec2& antenna, const Eigen::Matrix2d& covariance) {
  // Position from the first valid fix, heading assumed, at rest [Forklift thesis, eq. 4.14]. The printed
  // vector puts the antenna position itself into x, y; inverting eq. 4.13 at the assumed heading
  // removes the 5 cm antenna offset as well.
  const double th = params_.initial_heading;
  const geometry::Vec2 off = rotate(th, params_.antenna_offset);
  x_ = StateVector::Zero();
  x_(kX) = antenna.x - off.x;
  x_(kY) = antenna.y - off.y;
  x_(kTheta) = th;
  const double pos2 = params_.init_position_std * params_.init_position_std;
  const double vel2 = params_.init_velocity_std * params_.init_velocity_std;
  P_ = StateCovariance::Zero();
  // The bias variance stays exactly 0 when the bias is not estimated: b = 0 is then a constant and
  // the filter is the thesis's six-state one.
  const double bias2 = params_.gyro_bias ? params_.init_gyro_bias_std * params_.init_gyro_bias_std : 0.0;
  P_.diagonal() << pos2, pos2, params_.init_heading_std * params_.init_heading_std, vel2, vel2, vel2, bias2;
  if (params_.use_fix_covariance) P_.block<2, 2>(kX, kX) += measurement_noise(covariance);
  initialized_ = true;
  heading_resolved_ = !params_.heading_init;
  consecutive_rejections_ = 0;
  nis_mean_ = 2.0;
  if (!heading_resolved_) {
    P_(kTheta, kTheta) = kPi * kPi;
    dr_yaw_ = 0.0;
    dr_position_ = {};
    track_.clear();
    track_.push_back({params_.antenna_offset, antenna, 0.5 * measurement_noise(covariance).trace()});
  }
}

bool Ekf::predict(double gyro_omega, double dt) {
  if (!std::isfinite(gyro_omega) || !std::isfinite(dt) || dt <= 0.0) return false;
  last_gyro_ = gyro_omega;
  have_gyro_ = true;
  if (command_zero_) zero_command_for_ += dt;
  if (!initialized_) return false;
  if (!heading_resolved_) track_heading(gyro_omega, dt);

  const StateCovariance g = motion_jacobian(x_, dt);  // at mu_{t-1}, eq. 4.15
  x_ = motion_model(x_, gyro_omega, dt);              // eq. 4.1 with 4.8
  x_(kTheta) = geometry::normalize_angle(x_(kTheta));
  StateCovariance r = StateCovariance::Zero();
  const double scale = dt / params_.nominal_dt;
  for (int i = 0; i < 6; ++i) r(i, i) = params_.process_noise[i] * scale;  // eq. 4.16
  if (params_.gyro_bias) {
    // Random walk of the bias: variance grows by (rate)^2 per second, as the gyro's does.
    r(kBias, kBias) = params_.gyro_bias_random_walk * params_.gyro_bias_random_walk * dt;
  }
  P_ = g * P_ * g.transpose() + r;  // eq. 4.2
  symmetrize(P_);
  // The placeholder heading must not leak into the other states through correlations.
  if (!heading_resolved_) decouple(kTheta);
  return true;
}

void Ekf::decouple(int i) {
  const double var = P_(i, i);
  P_.row(i).setZero();
  P_.col(i).setZero();
  P_(i, i) = var;
}

void Ekf::track_heading(double gyro_omega, double dt) {
  // Dead reckoning in the frame of the body at the first fix: gyro for rotation, the latest
  // velocity measurement for translation (midpoint heading over the step).
  const double rate = gyro_omega - x_(kBias);  // the raw reading when the bias is not estimated
  const double mid = dr_yaw_ + 0.5 * rate * dt;
  if (have_velocity_) {
    dr_position_ = dr_position_ + dt * rotate(mid, {last_velocity_.vx, last_velocity_.vy});
  }
  dr_yaw_ += rate * dt;
}

void Ekf::try_resolve_heading() {
  if (track_.size() < 3) return;
  double theta_now = 0.0;
  double theta_var = 0.0;
  geometry::Vec2 position;
  if (have_velocity_) {
    // Distance travelled by dead reckoning, as seen from the first track point.
    double spread = 0.0;
    for (const TrackPoint& p : track_) {
      spread = std::max(spread, geometry::distance(p.dead_reckoned_antenna, track_.front().dead_reckoned_antenna));
    }
    if (spread < params_.heading_init_distance) return;
    // 2-D Procrustes: the rotation theta_0 and translation t minimising
    // sum w_k |fix_k - (R(theta_0) d_k + t)|^2 over the dead-reckoned antenna points d_k, with
    // w_k = 1 / variance_k. Fit, drop fixes outside their 99.7 % ellipse (NLOS), fit again.
    std::vector<bool> use(track_.size(), true);
    double theta0 = 0.0;
    geometry::Vec2 t;
    double sum_wd2 = 0.0;
    for (int pass = 0; pass < 2; ++pass) {
      geometry::Vec2 cd;
      geometry::Vec2 cf;
      double wsum = 0.0;
      for (std::size_t i = 0; i < track_.size(); ++i) {
        if (!use[i]) continue;
        const double w = 1.0 / track_[i].variance;
        cd = cd + w * track_[i].dead_reckoned_antenna;
        cf = cf + w * track_[i].fix;
        wsum += w;
      }
      if (wsum <= 0.0) return;
      cd = (1.0 / wsum) * cd;
      cf = (1.0 / wsum) * cf;
      double sc = 0.0;
      double sd = 0.0;
      sum_wd2 = 0.0;
      for (std::size_t i = 0; i < track_.size(); ++i) {
        if (!use[i]) continue;
        const double w = 1.0 / track_[i].variance;
        const geometry::Vec2 d = track_[i].dead_reckoned_antenna - cd;
        const geometry::Vec2 f = track_[i].fix - cf;
        sc += w * geometry::cross(d, f);
        sd += w * geometry::dot(d, f);
        sum_wd2 += w * geometry::dot(d, d);
      }
      theta0 = std::atan2(sc, sd);
      t = cf - rotate(theta0, cd);
      int kept = 0;
      for (std::size_t i = 0; i < track_.size(); ++i) {
        const geometry::Vec2 r = track_[i].fix - (rotate(theta0, track_[i].dead_reckoned_antenna) + t);
        use[i] = geometry::dot(r, r) <= 11.8 * track_[i].variance;  // chi-square 2 dof, 99.7 %
        kept += use[i] ? 1 : 0;
      }
      if (kept < 3) break;  // keep the first fit rather than fit on too few points
    }
    position = rotate(theta0, dr_position_) + t;
    theta_now = theta0 + dr_yaw_;
    // Rotation uncertainty of the weighted fit, plus the dead-reckoning scale and slip errors it
    // ignores.
    theta_var = 1.0 / std::max(sum_wd2, 1e-6) + 0.02 * 0.02;
  } else {
    // No velocity source: assume the forklift drove forwards, as the thesis's path follower does.
    const geometry::Vec2 d = track_.back().fix - track_.front().fix;
    if (geometry::norm(d) < params_.heading_init_distance) return;
    theta_now = std::atan2(d.y, d.x) + 0.5 * dr_yaw_;
    position = track_.back().fix - rotate(theta_now, params_.antenna_offset);
    theta_var = 2.0 * params_.uwb_std * params_.uwb_std / geometry::dot(d, d) + 0.05 * 0.05;
  }
  // Keep the map-frame velocity: the body velocities were estimated against the placeholder.
  const double old_theta = x_(kTheta);
  const geometry::Vec2 v_map = rotate(old_theta, {x_(kVx), x_(kVy)});
  const geometry::Vec2 v_body = rotate(-theta_now, v_map);
  x_(kX) = position.x;
  x_(kY) = position.y;
  x_(kTheta) = geometry::normalize_angle(theta_now);
  if (have_velocity_) {
    x_(kVx) = last_velocity_.vx;
    x_(kVy) = last_velocity_.vy;
    x_(kOmega) = last_velocity_.omega;
  } else {
    x_(kVx) = v_body.x;
    x_(kVy) = v_body.y;
  }
  P_.row(kTheta).setZero();
  P_.col(kTheta).setZero();
  P_(kTheta, kTheta) = theta_var;
  // The bias keeps its variance; its correlation with the new heading starts at zero.
  heading_resolved_ = true;
  track_.clear();
}

bool Ekf::passes_gate(const Eigen::Vector2d& innovation, const Eigen::Matrix<double, 2, kStateSize>& h,
                      const Eigen::Matrix2d& q, const Eigen::Matrix2d& widening, Eigen::Matrix2d& s, double& nis) {
  s = h * P_ * h.transpose() + q;
  nis = innovation.dot(s.ldlt().solve(innovation));
  if (!std::isfinite(nis)) return false;
  if (params_.gating && nis > params_.gate_chi2) {
    ++consecutive_rejections_;
    if (consecutive_rejections_ < params_.max_consecutive_rejections) return false;
    // Too many rejections in a row: the estimate, not the measurements, is off. Widen the position
    // uncertainty to cover the innovation and accept.
    P_.block<2, 2>(kX, kX) += widening;
    s = h * P_ * h.transpose() + q;
    nis = innovation.dot(s.ldlt().solve(innovation));
  }
  consecutive_rejections_ = 0;
  return true;
}

UpdateStatus Ekf::update_uwb(const geometry::Vec2& z_pos, const Eigen::Matrix2d& covariance) {
  if (!std::isfinite(z_pos.x) || !std::isfinite(z_pos.y) || !covariance.allFinite()) {
    return UpdateStatus::kRejectedNonFinite;
  }
  if (!initialized_) {
    if (params_.use_fix_covariance) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(0.5 * (covariance + covariance.transpose()));
      const double worst = eig.eigenvalues().maxCoeff();
      if (!(worst <= params_.init_max_fix_std * params_.init_max_fix_std)) return UpdateStatus::kNotInitialized;
    }
    initialize(z_pos, covariance);  // Fig. 4.3, lines 1-3
    return UpdateStatus::kInitialized;
  }

  const Eigen::Vector2d z(z_pos.x, z_pos.y);                                                  // eq. 4.10
  Eigen::Matrix<double, 2, kStateSize> h = measurement_jacobian(x_, params_.antenna_offset);  // eq. 4.17
  if (!heading_resolved_) h.col(kTheta).setZero();
  const Eigen::Vector2d innovation = z - measurement_model(x_, params_.antenna_offset);  // eq. 4.13
  const Eigen::Matrix2d q = measurement_noise(covariance);
  Eigen::Matrix2d s;
  double nis = 0.0;
  if (!passes_gate(innovation, h, q, innovation * innovation.transpose(), s, nis)) {
    return std::isfinite(nis) ? UpdateStatus::kGated : UpdateStatus::kRejectedNonFinite;
  }

  if (!heading_resolved_) {
    track_.push_back({rotate(dr_yaw_, params_.antenna_offset) + dr_position_, z_pos, 0.5 * q.trace()});
  }

  const Eigen::Matrix<double, kStateSize, 2> k = P_ * h.transpose() * s.inverse();  // eq. 4.3
  x_ += k * innovation;                                                             // eq. 4.4
  x_(kTheta) = geometry::normalize_angle(x_(kTheta));
  P_ = (StateCovariance::Identity() - k * h) * P_;  // eq. 4.5
  symmetrize(P_);
  nis_mean_ += 0.05 * (std::min(nis, 50.0) - nis_mean_);

  if (!heading_resolved_) try_resolve_heading();
  return UpdateStatus::kAccepted;
}

UpdateStatus Ekf::update_commanded(const BodyVelocity& cmd) {
  if (params_.standstill_update) {
    if (!finite(cmd)) return UpdateStatus::kRejectedNonFinite;
    // Exactly zero: the drive was told to stop. predict() counts how long ago that was, so the
    // first standstill_delay seconds (wheels still spinning down) get the ordinary update.
    const bool zero = cmd.vx == 0.0 && cmd.vy == 0.0 && cmd.omega == 0.0;
    if (!zero) zero_command_for_ = 0.0;
    command_zero_ = zero;
    if (zero && zero_command_for_ >= params_.standstill_delay) return update_standstill();
  }
  if (params_.velocity_source != VelocitySource::kCommanded) return UpdateStatus::kIgnored;
  return update_velocity(cmd, params_.commanded_velocity_std);
}

UpdateStatus Ekf::update_standstill() {
  if (!params_.standstill_update) return UpdateStatus::kIgnored;
  last_velocity_ = {};
  have_velocity_ = true;
  if (!initialized_) return UpdateStatus::kNotInitialized;
  if (!heading_resolved_) return UpdateStatus::kDeferred;
  // Zero-velocity update: z = (vx, vy, omega) = 0. With the bias state, the gyro reading taken at
  // rest adds z = gyro = omega + b (+ white noise), which is what makes b observable without any
  // heading information from the fixes. That reading also drove the last prediction; the
  // correlation this ignores is one step's worth of gyro noise on theta (about 1e-4 rad).
  if (params_.gyro_bias && have_gyro_) {
    Eigen::Matrix<double, 4, kStateSize> h = Eigen::Matrix<double, 4, kStateSize>::Zero();
    h(0, kVx) = 1.0;
    h(1, kVy) = 1.0;
    h(2, kOmega) = 1.0;
    h(3, kOmega) = 1.0;
    h(3, kBias) = 1.0;
    const auto& sd = params_.standstill_velocity_std;
    const Eigen::Vector4d z(0.0, 0.0, 0.0, last_gyro_);
    const Eigen::Vector4d var(sd[0] * sd[0], sd[1] * sd[1], sd[2] * sd[2],
                              params_.gyro_noise_std * params_.gyro_noise_std);
    linear_update<4>(x_, P_, h, z, var);
  } else {
    Eigen::Matrix<double, 3, kStateSize> h = Eigen::Matrix<double, 3, kStateSize>::Zero();
    h(0, kVx) = 1.0;
    h(1, kVy) = 1.0;
    h(2, kOmega) = 1.0;
    const auto& sd = params_.standstill_velocity_std;
    const Eigen::Vector3d var(sd[0] * sd[0], sd[1] * sd[1], sd[2] * sd[2]);
    linear_update<3>(x_, P_, h, Eigen::Vector3d::Zero(), var);
  }
  x_(kTheta) = geometry::normalize_angle(x_(kTheta));
  symmetrize(P_);
  return UpdateStatus::kAccepted;
}

UpdateStatus Ekf::update_encoders(const BodyVelocity& measured) {
  if (params_.velocity_source != VelocitySource::kEncoders) return UpdateStatus::kIgnored;
  return update_velocity(measured, params_.encoder_velocity_std);
}

UpdateStatus Ekf::update_velocity(const BodyVelocity& z, const std::array<double, 3>& std) {
  if (!finite(z)) return UpdateStatus::kRejectedNonFinite;
  last_velocity_ = z;
  have_velocity_ = true;
  if (!initialized_) return UpdateStatus::kNotInitialized;
  if (!heading_resolved_) return UpdateStatus::kDeferred;
  // z = (vx, vy, omega), H = [0 | I3]: a linear update on the velocity block.
  const Eigen::Vector3d innovation(z.vx - x_(kVx), z.vy - x_(kVy), z.omega - x_(kOmega));
  const Eigen::Matrix<double, kStateSize, 3> pht = P_.block<kStateSize, 3>(0, kVx);
  Eigen::Matrix3d s = P_.block<3, 3>(kVx, kVx);
  for (int i = 0; i < 3; ++i) s(i, i) += std[i] * std[i];
  const Eigen::Matrix<double, kStateSize, 3> k = pht * s.inverse();
  x_ += k * innovation;
  x_(kTheta) = geometry::normalize_angle(x_(kTheta));
  P_ -= k * pht.transpose();
  symmetrize(P_);
  return UpdateStatus::kAccepted;
}

geometry::Pose2 Ekf::pose() const {
  return {x_(kX), x_(kY), x_(kTheta)};
}

BodyVelocity Ekf::velocity() const {
  return {x_(kVx), x_(kVy), x_(kOmega)};
}

double Ekf::score() const {
  if (!initialized_) return 0.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(P_.block<2, 2>(kX, kX));
  const double pos_std = std::sqrt(std::max(eig.eigenvalues().maxCoeff(), 0.0));
  const double th_std = std::sqrt(std::max(P_(kTheta, kTheta), 0.0));
  const double ref_pos = 0.05;
  const double ref_th = 5.0 * kPi / 180.0;
  const double cov_term =
      1.0 / (1.0 + (pos_std / ref_pos) * (pos_std / ref_pos) + (th_std / ref_th) * (th_std / ref_th));
  const double nis_term = std::exp(-std::max(0.0, nis_mean_ - 2.0) / 4.0);
  double s = std::clamp(cov_term * nis_term, 0.0, 1.0);
  if (!heading_resolved_) s = std::min(s, 0.2);
  return s;
}

}  // namespace fleet::localization
