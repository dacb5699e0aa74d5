#include "perception/box_marker_camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace fleet::perception {

double DepthMarkerCameraParams::read_range(double speed) const {
  constexpr double kSlow = 0.3;
  constexpr double kFast = 1.0;
  const double k = (std::abs(speed) - kSlow) / (kFast - kSlow);
  const double range = read_range_slow + k * (read_range_fast - read_range_slow);
  return std::clamp(std::min(range, read_range_slow), range_min, range_max);
}

DepthMarkerCamera::DepthMarkerCamera(DepthMarkerCameraParams params, std::uint64_t seed)
    : params_(std::move(params)), rng_(seed) {
  if (!(params_.rate_hz > 0.0)) throw std::invalid_argument("depth marker camera: rate_hz must be > 0");
  if (!(params_.range_max > params_.range_min)) {
    throw std::invalid_argument("depth marker camera: range_max must exceed range_min");
  }
  if (!(params_.miss_rate >= 0.0 && params_.miss_rate <= 1.0)) {
    throw std::invalid_argument("depth marker camera: miss_rate must be in [0, 1], got " +
                                std::to_string(params_.miss_rate));
  }
}

void DepthMarkerCamera::look_at(const Eigen::Vector3d& target) {
  const Eigen::Vector3d ray = target - params_.mount;
  pan_ = std::atan2(ray.y(), ray.x());
  tilt_ = std::atan2(ray.z(), std::hypot(ray.x(), ray.y()));
}

bool DepthMarkerCamera::ideal(const geometry::Pose2& robot, const BoxMarker& marker, double speed,
                              BoxSighting& out) const {
  // Map -> base frame [Picker thesis, section 4.4.1]: the base's yaw and position on the floor.
  const geometry::Vec2 flat = geometry::map_to_body(robot, {marker.top_centre.x(), marker.top_centre.y()});
  const Eigen::Vector3d in_base(flat.x, flat.y, marker.top_centre.z());
  const Eigen::Vector3d ray = in_base - params_.mount;
  const double d = ray.norm();
  if (d < params_.range_min || d > params_.read_range(speed)) return false;
  // Base -> camera: undo the pan about z, then the tilt about the camera's y.
  const Eigen::Vector3d in_pan = Eigen::AngleAxisd(-pan_, Eigen::Vector3d::UnitZ()) * ray;
  const Eigen::Vector3d in_camera = Eigen::AngleAxisd(tilt_, Eigen::Vector3d::UnitY()) * in_pan;
  if (in_camera.x() <= 0.0) return false;
  if (std::abs(std::atan2(in_camera.y(), in_camera.x())) > params_.half_hfov) return false;
  if (std::abs(std::atan2(in_camera.z(), in_camera.x())) > params_.half_vfov) return false;
  // The printed face looks up: the camera must see it from above, within the viewing angle.
  const double off_normal = std::acos(std::clamp(-ray.z() / d, -1.0, 1.0));
  if (off_normal > params_.max_view_angle) return false;
  out.distance = d;
  out.top_centre = in_base;
  out.yaw = geometry::normalize_angle(marker.yaw - robot.yaw);
  out.id = marker.id;
  return true;
}

std::vector<BoxSighting> DepthMarkerCamera::capture(double t, const geometry::Pose2& robot,
                                                    std::span<const BoxMarker> markers, double speed) {
  const double period = 1.0 / params_.rate_hz;
  next_frame_ = (t - next_frame_ > period) ? t + period : next_frame_ + period;
  std::vector<BoxSighting> out;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (const BoxMarker& marker : markers) {
    BoxSighting sighting;
    if (!ideal(robot, marker, speed, sighting)) continue;
    // Every number is drawn for a visible marker, read or not, so the miss rate does not reshuffle the noise.
    const double u = uniform(rng_);
    const Eigen::Vector3d n(gauss(rng_), gauss(rng_), gauss(rng_));
    const double n_yaw = gauss(rng_);
    if (u < params_.miss_rate) continue;
    const double sigma =
        params_.sigma_position + params_.sigma_position_quadratic * sighting.distance * sighting.distance;
    sighting.time = t;
    sighting.top_centre += sigma * n;
    sighting.yaw = geometry::normalize_angle(sighting.yaw + params_.sigma_yaw * n_yaw);
    out.push_back(sighting);
  }
  return out;
}

}  // namespace fleet::perception
