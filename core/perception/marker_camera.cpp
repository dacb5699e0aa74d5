#include "perception/marker_camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "geometry/marker_sight.hpp"

namespace fleet::perception {

using geometry::angle_diff;
using geometry::normalize_angle;
using geometry::Pose2;
using geometry::Vec2;

MarkerCamera::MarkerCamera(MarkerCameraParams params, std::uint64_t seed)
    : params_(params), rng_(seed), bias_rng_(seed ^ 0x9e3779b97f4a7c15ULL) {
  if (!(params_.rate_hz > 0.0)) throw std::invalid_argument("marker camera: rate_hz must be > 0");
  if (!(params_.miss_rate >= 0.0 && params_.miss_rate <= 1.0)) {
    throw std::invalid_argument("marker camera: miss_rate must be in [0, 1], got " + std::to_string(params_.miss_rate));
  }
  if (!(params_.range_max > params_.range_min)) {
    throw std::invalid_argument("marker camera: range_max must exceed range_min");
  }
  if (!(params_.max_pan >= 0.0 && params_.max_pan <= std::numbers::pi)) {
    throw std::invalid_argument("marker camera: max_pan must be in [0, pi], got " + std::to_string(params_.max_pan));
  }
}

MarkerCameraParams MarkerCameraParams::axis_ptz() {
  MarkerCameraParams p;
  p.rate_hz = 30.0;
  // Front-right corner of the 0.65 x 0.50 m base, at 45° to the robot's heading [Picker thesis, section 3.1.1].
  p.camera_x = 0.30;
  p.camera_y = -0.22;
  p.camera_yaw = -std::numbers::pi / 4;
  p.max_pan = std::numbers::pi;  // ±180° pan
  p.half_fov = 0.40;             // about 46° at no zoom; the seed gives none
  p.range_min = 0.5;             // Experiment 1 began seeing the wall marker at 2.4 m only because of its tilt
  p.range_max = 10.5;            // "still able to detect the marker beyond the distance of 10 meters"
  p.max_view_angle = 1.2;
  // Distance error [Picker thesis, section 4.2.9.2.1, Fig. 4.7]: the detected distance overlaps the lidar's up to
  // almost 4 m ("a good pose of the robot till a distance of almost 4 meters"), then drifts away smoothly, below
  // 30 cm to 5.5 m and about 1 m near 10 m, read as 3 sigma. A drift that smooth is systematic, so per marker:
  // 1 cm at any range (its placement and printed size) and k (d - 4 m) beyond 4 m with k of 0.06 (1 sigma),
  // 9 cm at 5.5 m and 36 cm at 10 m; per frame 1 cm + 0.001 d^2.
  p.sigma_d = 0.01;
  p.sigma_d_rel = 0.0;
  p.sigma_d_quadratic = 0.001;
  p.sigma_d_bias = 0.01;
  p.sigma_d_bias_beyond = 0.06;
  p.exact_range = 4.0;
  p.sigma_alpha = 0.005;       // a few pixels of the marker's centre
  p.sigma_alpha_bias = 0.005;  // the marker's placement on its pillar, about 1 cm at 2 m
  p.sigma_gamma = 0.05;        // a marker's orientation at range is poor; the filter does not use it
  p.miss_rate = 0.05;
  p.miss_rate_per_speed = 0.25;  // detection "stops at some intervals" at 1.0 m/s (Picker thesis, Fig. 4.8)
  return p;
}

double MarkerCameraParams::distance_std(double d) const {
  const double frame = sigma_d + sigma_d_rel * d + sigma_d_quadratic * d * d;
  return std::hypot(frame, sigma_d_bias, sigma_d_bias_beyond * std::max(0.0, d - exact_range));
}

double MarkerCameraParams::bearing_std() const {
  return std::hypot(sigma_alpha, sigma_alpha_bias);
}

const MarkerCamera::Bias& MarkerCamera::bias_of(int marker_id) {
  auto it = biases_.find(marker_id);
  if (it != biases_.end()) return it->second;
  std::normal_distribution<double> gauss(0.0, 1.0);
  Bias bias;
  bias.d = gauss(bias_rng_) * params_.sigma_d_bias;
  bias.d_beyond = gauss(bias_rng_) * params_.sigma_d_bias_beyond;
  bias.alpha = gauss(bias_rng_) * params_.sigma_alpha_bias;
  return biases_.emplace(marker_id, bias).first->second;
}

void MarkerCamera::set_pan(double pan) {
  pan_ = std::clamp(normalize_angle(pan), -params_.max_pan, params_.max_pan);
}

CameraMount MarkerCamera::mount() const {
  CameraMount m;
  m.x = params_.camera_x;
  m.y = params_.camera_y;
  m.pan = normalize_angle(params_.camera_yaw + pan_);
  return m;
}

bool MarkerCamera::frame_due(double t) const {
  return t >= next_frame_time_;
}

Pose2 camera_pose(const Pose2& robot, double camera_x) {
  CameraMount m;
  m.x = camera_x;
  return camera_pose(robot, m);
}

Pose2 camera_pose(const Pose2& robot, const CameraMount& mount) {
  const Vec2 c = geometry::body_to_map(robot, {mount.x, mount.y});
  return {c.x, c.y, normalize_angle(robot.yaw + mount.pan)};
}

bool MarkerCamera::ideal_measurement(const Pose2& robot_truth, const Marker& marker, MarkerDetection& out) const {
  const Pose2 cam = camera_pose(robot_truth, mount());
  const Vec2 rel = geometry::map_to_body(cam, marker.pose.position());
  const double d = geometry::norm(rel);
  if (d < params_.range_min || d > params_.range_max) return false;
  const double alpha = std::atan2(rel.y, rel.x);
  if (rel.x <= 0.0 || std::abs(alpha) > params_.half_fov) return false;
  // [Forklift thesis, Fig. 6.6]: gamma is zero when the optical axis points straight into the printed face.
  const double gamma = angle_diff(marker.pose.yaw + std::numbers::pi, cam.yaw);
  if (std::abs(gamma) > params_.max_view_angle) return false;
  // A marker seen from behind its face cannot be decoded: the face normal must point at the camera.
  const Vec2 normal{std::cos(marker.pose.yaw), std::sin(marker.pose.yaw)};
  if (geometry::dot(normal, cam.position() - marker.pose.position()) <= 0.0) return false;
  const Vec2 face = geometry::marker_sight_point(marker.pose);
  for (const auto& occluder : occluders_) {
    if (geometry::segment_intersects_polygon(cam.position(), face, occluder)) return false;
  }
  out.id = marker.id;
  out.d = d;
  out.alpha = alpha;
  out.gamma = gamma;
  return true;
}

std::vector<MarkerDetection> MarkerCamera::capture(double t, const Pose2& robot_truth, std::span<const Marker> markers,
                                                   double speed) {
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
    if (u < params_.miss_rate + params_.miss_rate_per_speed * std::abs(speed)) continue;
    det.time = t;
    const Bias& bias = bias_of(marker.id);
    det.d += nd * (params_.sigma_d + params_.sigma_d_rel * det.d + params_.sigma_d_quadratic * det.d * det.d) + bias.d +
             bias.d_beyond * std::max(0.0, det.d - params_.exact_range);
    det.alpha = normalize_angle(det.alpha + na * params_.sigma_alpha + bias.alpha);
    det.gamma = normalize_angle(det.gamma + ng * params_.sigma_gamma);
    detections.push_back(det);
  }
  return detections;
}

int aim_at_nearest_marker(MarkerCamera& camera, const Pose2& estimate, std::span<const Marker> markers,
                          int other_than) {
  const MarkerCameraParams& p = camera.params();
  CameraMount at_rest;
  at_rest.x = p.camera_x;
  at_rest.y = p.camera_y;
  at_rest.pan = p.camera_yaw;
  const Pose2 rest = camera_pose(estimate, at_rest);
  int best = -1;
  double best_d = p.range_max;
  double best_pan = camera.pan();
  for (const Marker& marker : markers) {
    if (marker.id == other_than) continue;
    const Vec2 to = marker.pose.position() - rest.position();
    const double d = geometry::norm(to);
    if (d < p.range_min || d >= best_d) continue;
    const double pan = angle_diff(std::atan2(to.y, to.x), rest.yaw);
    if (std::abs(pan) > p.max_pan) continue;
    const double gamma = angle_diff(marker.pose.yaw + std::numbers::pi, rest.yaw + pan);
    const Vec2 normal{std::cos(marker.pose.yaw), std::sin(marker.pose.yaw)};
    if (std::abs(gamma) > p.max_view_angle || geometry::dot(normal, -1.0 * to) <= 0.0) continue;
    best = marker.id;
    best_d = d;
    best_pan = pan;
  }
  if (best >= 0) camera.set_pan(best_pan);
  return best;
}

Marker marker_from_detection(const Pose2& robot, double camera_x, const MarkerDetection& det) {
  CameraMount m;
  m.x = camera_x;
  return marker_from_detection(robot, m, det);
}

Marker marker_from_detection(const Pose2& robot, const CameraMount& mount, const MarkerDetection& det) {
  const Pose2 cam = camera_pose(robot, mount);
  const double bearing = cam.yaw + det.alpha;
  Marker m;
  m.id = det.id;
  m.pose = {cam.x + det.d * std::cos(bearing), cam.y + det.d * std::sin(bearing),
            normalize_angle(cam.yaw + det.gamma + std::numbers::pi)};
  return m;
}

}  // namespace fleet::perception
