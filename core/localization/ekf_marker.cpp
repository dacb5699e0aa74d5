// The picker's localization by markers at known places [Picker thesis, section 4.2.9]: a start at a known pose
// and range-and-bearing updates from marker sightings, in the same filter as the forklift's UWB fixes.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "localization/ekf.hpp"

namespace fleet::localization {

namespace {

/// The camera's optical centre on the map and its derivative by the heading, for the state x.
struct CameraOnMap {
  Eigen::Vector2d position;
  Eigen::Vector2d d_theta;
};

CameraOnMap camera_on_map(const StateVector& x, const MarkerSighting& z) {
  const double c = std::cos(x(kTheta));
  const double s = std::sin(x(kTheta));
  const double cx = z.camera.x;
  const double cy = z.camera.y;
  return {{x(kX) + c * cx - s * cy, x(kY) + s * cx + c * cy}, {-s * cx - c * cy, c * cx - s * cy}};
}

bool finite(const MarkerSighting& z) {
  return std::isfinite(z.marker.x) && std::isfinite(z.marker.y) && std::isfinite(z.camera.x) &&
         std::isfinite(z.camera.y) && std::isfinite(z.camera_yaw) && std::isfinite(z.d) && std::isfinite(z.alpha) &&
         std::isfinite(z.sigma_d) && std::isfinite(z.sigma_alpha) && z.sigma_d > 0.0 && z.sigma_alpha > 0.0;
}

}  // namespace

EkfParams EkfParams::picker() {
  EkfParams p;
  // Per 70 Hz step: the mecanum base moves sideways as readily as forwards, so vy gets vx's noise.
  p.process_noise = {1e-6, 1e-6, 2e-6, 2e-5, 2e-5, 1e-4};
  p.velocity_source = VelocitySource::kEncoders;
  p.encoder_velocity_std = {0.01, 0.01, 0.02};  // [Picker thesis, eq. 3.7] with roller slip
  p.gating = true;
  p.init_position_std = 0.05;
  p.init_heading_std = 0.02;
  // The MEMS gyro's bias wanders (MarkerLocalizerParams::gyro): unestimated, a robot standing a
  // minute turned its heading estimate by a tenth of a radian between marker corrections. Every
  // stop calibrates it (update 5); the markers' bearings pull it in while driving.
  p.gyro_bias = true;
  p.standstill_update = true;
  return p;
}

void Ekf::initialize_at(const geometry::Pose2& pose, double position_std, double heading_std) {
  x_ = StateVector::Zero();
  x_(kX) = pose.x;
  x_(kY) = pose.y;
  x_(kTheta) = geometry::normalize_angle(pose.yaw);
  const double vel2 = params_.init_velocity_std * params_.init_velocity_std;
  const double bias2 = params_.gyro_bias ? params_.init_gyro_bias_std * params_.init_gyro_bias_std : 0.0;
  P_ = StateCovariance::Zero();
  P_.diagonal() << position_std * position_std, position_std * position_std, heading_std * heading_std, vel2, vel2,
      vel2, bias2;
  initialized_ = true;
  heading_resolved_ = true;
  consecutive_rejections_ = 0;
  nis_mean_ = 2.0;
  track_.clear();
}

Eigen::Vector2d Ekf::marker_model(const StateVector& x, const MarkerSighting& z) {
  const CameraOnMap cam = camera_on_map(x, z);
  const Eigen::Vector2d rel = Eigen::Vector2d(z.marker.x, z.marker.y) - cam.position;
  const double bearing = std::atan2(rel.y(), rel.x()) - x(kTheta) - z.camera_yaw;
  return {rel.norm(), geometry::normalize_angle(bearing)};
}

Eigen::Matrix<double, 2, kStateSize> Ekf::marker_jacobian(const StateVector& x, const MarkerSighting& z) {
  const CameraOnMap cam = camera_on_map(x, z);
  const Eigen::Vector2d rel = Eigen::Vector2d(z.marker.x, z.marker.y) - cam.position;
  const double d2 = std::max(rel.squaredNorm(), 1e-12);
  const double d = std::sqrt(d2);
  // rel = marker - (p + R(theta) c): d rel / d(x, y) = -I, d rel / d theta = -d_theta.
  const Eigen::Vector2d dd_drel = rel / d;
  const Eigen::Vector2d dbearing_drel(-rel.y() / d2, rel.x() / d2);
  Eigen::Matrix<double, 2, kStateSize> h = Eigen::Matrix<double, 2, kStateSize>::Zero();
  h(0, kX) = -dd_drel.x();
  h(0, kY) = -dd_drel.y();
  h(0, kTheta) = -dd_drel.dot(cam.d_theta);
  h(1, kX) = -dbearing_drel.x();
  h(1, kY) = -dbearing_drel.y();
  h(1, kTheta) = -dbearing_drel.dot(cam.d_theta) - 1.0;
  return h;
}

UpdateStatus Ekf::update_marker(const MarkerSighting& z) {
  if (!finite(z)) return UpdateStatus::kRejectedNonFinite;
  if (!initialized_) return UpdateStatus::kNotInitialized;
  const Eigen::Vector2d predicted = marker_model(x_, z);
  const Eigen::Vector2d innovation(z.d - predicted(0), geometry::normalize_angle(z.alpha - predicted(1)));
  const Eigen::Matrix<double, 2, kStateSize> h = marker_jacobian(x_, z);
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  q(0, 0) = z.sigma_d * z.sigma_d;
  q(1, 1) = z.sigma_alpha * z.sigma_alpha;
  // Forced through after too many rejections: the position is off by about the range error and the
  // bearing error's arc, in any direction.
  const double off = std::hypot(innovation(0), predicted(0) * innovation(1));
  Eigen::Matrix2d s;
  double nis = 0.0;
  if (!passes_gate(innovation, h, q, off * off * Eigen::Matrix2d::Identity(), s, nis)) {
    return std::isfinite(nis) ? UpdateStatus::kGated : UpdateStatus::kRejectedNonFinite;
  }
  const Eigen::Matrix<double, kStateSize, 2> k = P_ * h.transpose() * s.inverse();
  x_ += k * innovation;
  x_(kTheta) = geometry::normalize_angle(x_(kTheta));
  P_ = (StateCovariance::Identity() - k * h) * P_;
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  nis_mean_ += 0.05 * (std::min(nis, 50.0) - nis_mean_);
  return UpdateStatus::kAccepted;
}

}  // namespace fleet::localization
