#include "perception/stacker_cameras.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "geometry/pose.hpp"

namespace fleet::perception {

namespace {
using ::fleet::geometry::kDeg;
}  // namespace

sim::DepthCameraParams stacker_tof(const sim::TricycleGeometry& g) {
  sim::DepthCameraParams p = sim::sick_3vistor_t(std::numbers::pi / 2);
  p.model.mount.x += 0.5 * (g.front_x() + g.fork_tip_x());
  return p;
}

sim::DepthCameraParams stacker_rear_camera(const sim::TricycleGeometry& g) {
  sim::DepthCameraParams p = sim::realsense_r200();
  p.model.mount.x = g.chassis_back_x();
  return p;
}

StackerCameraDetector::StackerCameraDetector(const sim::TricycleGeometry& geometry, PalletRow row,
                                             const StackerDetectorParams& params, std::uint64_t seed)
    : tof_(stacker_tof(geometry), seed),
      rear_(stacker_rear_camera(geometry), seed + 1),
      row_(std::move(row)),
      params_(params) {}

std::optional<geometry::Pose2> StackerCameraDetector::operator()(const geometry::Pose2& vehicle,
                                                                 const geometry::Pose2& expected, double t) {
  if (t + 1e-9 < next_) return std::nullopt;
  next_ = t + 1.0 / params_.rate_hz;
  const auto started = std::chrono::steady_clock::now();
  const geometry::Pose2 in_body = geometry::map_pose_to_body(vehicle, expected);
  const geometry::Vec2 face{in_body.x + 0.6 * std::cos(in_body.yaw), in_body.y + 0.6 * std::sin(in_body.yaw)};
  sim::DepthCamera& camera = pick_camera(face);
  PalletExpectation e;
  e.pallet = in_body;
  e.base_height = row_.base_height;
  e.area = params_.area;
  if (last_ && geometry::distance(last_->position(), expected.position()) > params_.track_radius) last_.reset();
  if (last_) e.roi_centre = geometry::map_pose_to_body(vehicle, *last_);
  const DepthImage image = camera.render(row_.scene, vehicle, detection_window(camera.model(), e));
  const Detection d = detect_pallet(image, camera.model(), e);
  times_ms_.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count());
  ++frames_;
  if (!d.found) {
    last_reason_ = (&camera == &rear_ ? "rear camera: " : "ToF camera: ") + d.reason;
    return std::nullopt;
  }
  ++found_;
  last_ = geometry::body_pose_to_map(vehicle, d.pallet_pose());
  return last_;
}

sim::DepthCamera& StackerCameraDetector::pick_camera(geometry::Vec2 face) {
  const auto& rear = rear_.model();
  const geometry::Vec2 from_rear{face.x - rear.mount.x, face.y - rear.mount.y};
  const double off_axis = std::abs(geometry::angle_diff(std::atan2(from_rear.y, from_rear.x), rear.mount.pan));
  const double range = std::hypot(from_rear.x, from_rear.y);
  if (off_axis < 0.5 * rear.hfov - 10.0 * kDeg && range > rear.min_range + 0.2 && range < rear.max_range - 0.5) {
    return rear_;
  }
  const auto& tof = tof_.model();
  const double bearing = std::atan2(face.y - tof.mount.y, face.x - tof.mount.x);
  tof_.set_pan_tilt(std::clamp(bearing, -std::numbers::pi / 2, std::numbers::pi / 2), tof.mount.tilt);
  return tof_;
}

}  // namespace fleet::perception
