#include "eval/marker_loc_eval.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>

#include "control/waypoint_controller.hpp"
#include "sim/encoders.hpp"
#include "sim/forklift_body.hpp"
#include "sim/summit_xls.hpp"

namespace fleet::eval {

namespace {

using geometry::Pose2;
using geometry::Vec2;

constexpr double kPeriod = 0.02;  // the encoders' and the waypoint controller's 50 Hz

struct ErrorSamples {
  std::vector<double> position;
  std::vector<double> heading;

  void add(const Pose2& truth, const Pose2& estimate) {
    position.push_back(std::hypot(estimate.x - truth.x, estimate.y - truth.y));
    heading.push_back(std::abs(geometry::angle_diff(estimate.yaw, truth.yaw)));
  }

  MarkerLocErrors summary() const {
    MarkerLocErrors e;
    if (position.empty()) return e;
    double sum2 = 0.0;
    double hsum2 = 0.0;
    for (double p : position) sum2 += p * p;
    for (double h : heading) hsum2 += h * h;
    std::vector<double> sorted = position;
    std::sort(sorted.begin(), sorted.end());
    const double to_deg = 180.0 / std::numbers::pi;
    e.rmse_cm = 100.0 * std::sqrt(sum2 / static_cast<double>(position.size()));
    e.p95_cm = 100.0 * sorted[static_cast<std::size_t>(0.95 * static_cast<double>(sorted.size() - 1))];
    e.max_cm = 100.0 * sorted.back();
    e.heading_rmse_deg = to_deg * std::sqrt(hsum2 / static_cast<double>(heading.size()));
    e.heading_max_deg = to_deg * *std::max_element(heading.begin(), heading.end());
    return e;
  }
};

/// The second PTZ camera: the rear-left corner, looking left [Picker thesis, section 3.1.1].
perception::MarkerCameraParams rear_left(perception::MarkerCameraParams p) {
  p.camera_x = -p.camera_x;
  p.camera_y = -p.camera_y;
  p.camera_yaw = geometry::normalize_angle(p.camera_yaw + std::numbers::pi);
  return p;
}

}  // namespace

std::vector<map::Marker> rack_aisle_markers(const MarkerLocEvalParams& params) {
  constexpr double kRackX0 = 33.5;
  constexpr double kPillarPitch = 3.5;  // [Picker thesis, section 4.2.9.3, Experiment 2]
  std::vector<map::Marker> markers;
  for (int k = 0; k <= 6; ++k) {
    const double x = kRackX0 + kPillarPitch * k;
    markers.push_back({100 + k, {x, params.south_face_y, std::numbers::pi / 2}, 1.0});
    markers.push_back({110 + k, {x, params.north_face_y, -std::numbers::pi / 2}, 1.0});
  }
  return markers;
}

MarkerLocEvalResult run_marker_loc_eval(const MarkerLocEvalParams& params) {
  if (!(params.duration > 0.0)) throw std::invalid_argument("marker loc-eval: duration must be > 0");
  if (!(params.fuse_rate_hz > 0.0)) throw std::invalid_argument("marker loc-eval: fuse_rate_hz must be > 0");
  if (!(params.speed > 0.0)) throw std::invalid_argument("marker loc-eval: speed must be > 0");
  const double south_lane = params.south_face_y + params.rack_distance;
  const double north_lane = params.north_face_y - params.rack_distance;
  if (!(north_lane >= south_lane)) {
    throw std::invalid_argument("marker loc-eval: rack_distance leaves no room between the rack faces");
  }
  const std::vector<map::Marker> site_markers = params.markers.empty() ? rack_aisle_markers(params) : params.markers;
  std::vector<perception::Marker> markers;
  for (const auto& m : site_markers) markers.push_back({m.id, m.pose});
  const auto marker_at = [&](int id) {
    return std::find_if(markers.begin(), markers.end(), [id](const perception::Marker& m) { return m.id == id; });
  };

  const Pose2 start{params.x_from, south_lane, 0.0};
  sim::ForkliftParams body_params = sim::summit_xls_body_params();
  sim::ForkliftBody body(body_params, start, std::mt19937_64(params.seed));
  sim::WheelEncoders encoders(sim::summit_xls_encoder_params(), std::mt19937_64(params.seed + 1));
  sim::WheelOdometry odometry(body_params.mecanum, start);
  std::vector<perception::MarkerCamera> cameras;
  cameras.emplace_back(params.camera, params.seed + 2);
  cameras.emplace_back(rear_left(params.camera), params.seed + 3);
  std::vector<geometry::Polygon> occluders = params.occluders;
  if (occluders.empty()) {
    constexpr double kRackDepth = 1.2;
    for (const double face : {params.south_face_y, params.north_face_y}) {
      const double back = face == params.south_face_y ? face - kRackDepth : face + kRackDepth;
      const double lo = std::min(face, back);
      const double hi = std::max(face, back);
      occluders.push_back({{33.5, lo}, {54.5, lo}, {54.5, hi}, {33.5, hi}});
    }
  }
  for (auto& camera : cameras) camera.set_occluders(occluders);

  localization::Ekf ekf(params.ekf);
  ekf.initialize_at(start, params.ekf.init_position_std, params.ekf.init_heading_std);

  control::WaypointControllerParams cp;
  cp.max_speed = params.speed;
  control::WaypointController controller(cp);
  // One lap east along the south face, one west along the north face; the base turns on the spot at each end.
  const std::vector<std::vector<Vec2>> legs{{{params.x_to, south_lane}, {params.x_to, north_lane}},
                                            {{params.x_from, north_lane}, {params.x_from, south_lane}}};
  std::size_t leg = 0;
  controller.set_waypoints(legs[0]);

  MarkerLocEvalResult r;
  ErrorSamples ekf_errors;
  ErrorSamples odometry_errors;
  std::set<int> seen;
  double last_accepted = 0.0;
  std::vector<double> next_fusion(cameras.size(), 0.0);
  Vec2 last_position = start.position();
  const int steps = static_cast<int>(std::ceil(params.duration / kPeriod));
  for (int i = 1; i <= steps; ++i) {
    const double t = i * kPeriod;
    const control::BodyTwist cmd = controller.update(ekf.pose());
    body.step({cmd.vx, cmd.vy, cmd.omega}, kPeriod);
    const sim::BodyTwist measured = odometry.update(encoders.measure(body.wheel_speeds(), kPeriod), kPeriod);
    // The wheels' yaw rate stands in for a gyro: the Summit-XLS of the thesis localises without one.
    ekf.predict(measured.omega, kPeriod);
    ekf.update_encoders({measured.vx, measured.vy, measured.omega});
    const double speed = std::hypot(body.twist().vx, body.twist().vy);
    for (std::size_t c = 0; c < cameras.size(); ++c) {
      auto& camera = cameras[c];
      if (!camera.frame_due(t)) continue;
      perception::aim_at_nearest_marker(camera, ekf.pose(), markers);
      const perception::CameraMount mount = camera.mount();
      for (const auto& det : camera.capture(t, body.pose(), markers, speed)) {
        const auto marker = marker_at(det.id);
        if (marker == markers.end()) continue;
        ++r.sightings;
        seen.insert(det.id);
        if (t < next_fusion[c]) continue;
        next_fusion[c] = t + 1.0 / params.fuse_rate_hz;
        const auto status = ekf.update_marker({marker->pose.position(),
                                               {mount.x, mount.y},
                                               mount.pan,
                                               det.d,
                                               det.alpha,
                                               params.camera.distance_std(det.d),
                                               params.camera.bearing_std()});
        if (status == localization::UpdateStatus::kGated) ++r.sightings_gated;
        if (status == localization::UpdateStatus::kAccepted) {
          ++r.sightings_fused;
          r.longest_gap_s = std::max(r.longest_gap_s, t - last_accepted);
          last_accepted = t;
        }
      }
    }
    ekf_errors.add(body.pose(), ekf.pose());
    odometry_errors.add(body.pose(), odometry.pose());
    r.distance_m += geometry::distance(body.pose().position(), last_position);
    last_position = body.pose().position();
    if (i % 25 == 0) {
      r.truth.push_back(body.pose());
      r.estimate.push_back(ekf.pose());
    }
    if (controller.done()) {
      ++r.laps;
      leg = 1 - leg;
      controller.set_waypoints(legs[leg]);
    }
  }
  r.longest_gap_s = std::max(r.longest_gap_s, params.duration - last_accepted);
  r.markers_seen = static_cast<int>(seen.size());
  r.ekf = ekf_errors.summary();
  r.odometry = odometry_errors.summary();
  return r;
}

}  // namespace fleet::eval
