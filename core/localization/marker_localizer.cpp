#include "localization/marker_localizer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fleet::localization {

namespace {

/// The second PTZ camera: the rear-left corner, the front-right one turned half round [Picker thesis, section 3.1.1].
perception::MarkerCameraParams rear_left(perception::MarkerCameraParams p) {
  p.camera_x = -p.camera_x;
  p.camera_y = -p.camera_y;
  p.camera_yaw = geometry::normalize_angle(p.camera_yaw + std::numbers::pi);
  return p;
}

}  // namespace

MarkerLocalizer::MarkerLocalizer(const MarkerLocalizerParams& params, const sim::MecanumParams& base,
                                 const geometry::Pose2& start, std::vector<perception::Marker> markers,
                                 std::vector<geometry::Polygon> occluders, std::mt19937_64 rng)
    : params_(params),
      markers_(std::move(markers)),
      encoders_(params.encoders, std::mt19937_64(rng())),
      odometry_(base, start),
      ekf_(params.ekf) {
  if (!(params_.fuse_rate_hz > 0.0)) throw std::invalid_argument("marker localizer: fuse_rate_hz must be > 0");
  cameras_.emplace_back(params_.camera, rng());
  cameras_.emplace_back(rear_left(params_.camera), rng());
  for (auto& camera : cameras_) camera.set_occluders(occluders);
  if (params_.gyro) gyro_.emplace(*params_.gyro, std::mt19937_64(rng()));
  next_fusion_.assign(cameras_.size(), 0.0);
  ekf_.initialize_at(start, params_.ekf.init_position_std, params_.ekf.init_heading_std);
}

void MarkerLocalizer::step(double t, double dt, const sim::BodyTwist& command, const sim::WheelSpeeds& wheels,
                           const geometry::Pose2& truth, double speed, double yaw_rate) {
  const sim::BodyTwist measured = odometry_.update(encoders_.measure(wheels, dt), dt);
  ekf_.predict(gyro_ ? gyro_->measure(yaw_rate, dt) : measured.omega, dt);
  const bool still = command.vx == 0.0 && command.vy == 0.0 && command.omega == 0.0;
  still_for_ = still ? still_for_ + dt : 0.0;
  if (still_for_ >= params_.ekf.standstill_delay) {
    ekf_.update_standstill();
  } else {
    ekf_.update_encoders({measured.vx, measured.vy, measured.omega});
  }
  int aimed_at = -1;  // the first camera's marker: the second looks at another where it can
  for (std::size_t c = 0; c < cameras_.size(); ++c) {
    auto& camera = cameras_[c];
    if (!camera.frame_due(t)) continue;
    const int other = perception::aim_at_nearest_marker(camera, ekf_.pose(), markers_, aimed_at);
    aimed_at = other >= 0 ? other : perception::aim_at_nearest_marker(camera, ekf_.pose(), markers_);
    const perception::CameraMount mount = camera.mount();
    // Each fusion takes the nearest marker in the frame, the one the camera is aimed at where it was decoded:
    // a marker's range error grows with its distance, and one farther off in the same frame (or the first one
    // listed) can be metres away.
    auto detections = camera.capture(t, truth, markers_, speed);
    std::sort(detections.begin(), detections.end(), [](const auto& a, const auto& b) { return a.d < b.d; });
    bool fuse = t >= next_fusion_[c];
    for (const auto& det : detections) {
      const auto marker =
          std::find_if(markers_.begin(), markers_.end(), [&](const perception::Marker& m) { return m.id == det.id; });
      if (marker == markers_.end()) continue;
      ++sightings_;
      if (std::find(seen_.begin(), seen_.end(), det.id) == seen_.end()) seen_.push_back(det.id);
      if (!fuse) continue;
      fuse = false;
      next_fusion_[c] = t + 1.0 / params_.fuse_rate_hz;
      const auto status = ekf_.update_marker({marker->pose.position(),
                                              {mount.x, mount.y},
                                              mount.pan,
                                              det.d,
                                              det.alpha,
                                              params_.camera.distance_std(det.d),
                                              params_.camera.bearing_std()});
      if (status == UpdateStatus::kGated) ++gated_;
      if (status == UpdateStatus::kAccepted) {
        ++fused_;
        longest_gap_ = std::max(longest_gap_, t - last_fused_);
        last_fused_ = t;
      }
    }
  }
}

}  // namespace fleet::localization
