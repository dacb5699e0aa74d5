#include "perception/marker_camera.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace fleet::perception {

using geometry::angle_diff;
using geometry::normalize_angle;
using geometry::Pose2;
using geometry::Vec2;

MarkerCamera::MarkerCamera(MarkerCameraParams params, std::uint64_t seed) : params_(params), rng_(seed) {
  if (!(params_.rate_hz > 0.0)) throw std::invalid_argument("marker camera: rate_hz must be > 0");
  if (!(params_.miss_rate >= 0.0 && params_.miss_rate <= 1.0)) {
    throw std::invalid_argument("marker camera: miss_rate must be in [0, 1], got " + std::to_string(params_.miss_rate));
  }
  if (!(params_.range_max > params_.range_min)) {
    throw std::invalid_argument("marker camera: range_max must exceed range_min");
  }
}

bool MarkerCamera::frame_due(double t) const {
  return t >= next_frame_time_;
}

Pose2 camera_pose(const Pose2& robot, double camera_x) {
  const Vec2 c = geometry::body_to_map(robot, {camera_x, 0.0});
  return {c.x, c.y, robot.yaw};
}

bool MarkerCamera::ideal_measurement(const Pose2& robot_truth, const Marker& marker, MarkerDetection& out) const {
  const Pose2 cam = camera_pose(robot_truth, params_.camera_x);
  const Vec2 rel = geometry::map_to_body(cam, marker.pose.position());
  const double d = geometry::norm(rel);
  if (d < params_.range_min || d > params_.range_max) return false;
  const double alpha = std::atan2(rel.y, rel.x);
  if (rel.x <= 0.0 || std::abs(alpha) > params_.half_fov) return false;
  // Fig. 6.6: gamma is zero when the optical axis points straight into the printed face.
  const double gamma = angle_diff(marker.pose.yaw + std::numbers::pi, cam.yaw);
  if (std::abs(gamma) > params_.max_view_angle) return false;
  // A marker seen from behind its face cannot be decoded: the face normal must point at the camera.
  const Vec2 normal{std::cos(marker.pose.yaw), std::sin(marker.pose.yaw)};
  if (geometry::dot(normal, cam.position() - marker.pose.position()) <= 0.0) return false;
  out.id = marker.id;
  out.d = d;
  out.alpha = alpha;
  out.gamma = gamma;
  return true;
}

std::vector<MarkerDetection> MarkerCamera::capture(double t, const Pose2& robot_truth,
                                                   std::span<const Marker> markers) {
  const double period = 1.0 / params_.rate_hz;
  // Keep the frame grid regular even when called late, without bursts to catch up.
  next_frame_time_ = (t - next_frame_time_ > period) ? t + period : next_frame_time_ + period;

  std::vector<MarkerDetection> detections;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (const Marker& marker : markers) {
    MarkerDetection det;
    if (!ideal_measurement(robot_truth, marker, det)) continue;
    // Draw every random number for a visible marker whether or not it is missed, so changing
    // the miss rate does not reshuffle the noise of the other frames.
    const double u = uniform(rng_);
    const double nd = gauss(rng_);
    const double na = gauss(rng_);
    const double ng = gauss(rng_);
    if (u < params_.miss_rate) continue;
    det.time = t;
    det.d += nd * (params_.sigma_d + params_.sigma_d_rel * det.d);
    det.alpha = normalize_angle(det.alpha + na * params_.sigma_alpha);
    det.gamma = normalize_angle(det.gamma + ng * params_.sigma_gamma);
    detections.push_back(det);
  }
  return detections;
}

Marker marker_from_detection(const Pose2& robot, double camera_x, const MarkerDetection& det) {
  const Pose2 cam = camera_pose(robot, camera_x);
  const double bearing = cam.yaw + det.alpha;
  Marker m;
  m.id = det.id;
  m.pose = {cam.x + det.d * std::cos(bearing), cam.y + det.d * std::sin(bearing),
            normalize_angle(cam.yaw + det.gamma + std::numbers::pi)};
  return m;
}

}  // namespace fleet::perception
