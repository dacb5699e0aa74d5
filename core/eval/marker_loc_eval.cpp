#include "eval/marker_loc_eval.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include "common/percentile.hpp"
#include "control/waypoint_controller.hpp"
#include "localization/marker_localizer.hpp"
#include "sim/forklift_body.hpp"
#include "sim/summit_xls.hpp"

namespace fleet::eval {

namespace {

using geometry::Pose2;
using geometry::Vec2;

constexpr double kPeriod = 0.02;  // the encoders' and the waypoint controller's 50 Hz
// The plant's rack rows: from x = 33.5 m, six bays between pillars 3.5 m apart [Picker thesis, section 4.2.9.3].
constexpr double kRackX0 = 33.5;
constexpr double kPillarPitch = 3.5;
constexpr int kBays = 6;

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
    const double to_deg = 180.0 / std::numbers::pi;
    e.rmse_cm = 100.0 * std::sqrt(sum2 / static_cast<double>(position.size()));
    e.p95_cm = 100.0 * common::percentile(position, 0.95);
    e.max_cm = 100.0 * *std::max_element(position.begin(), position.end());
    e.heading_rmse_deg = to_deg * std::sqrt(hsum2 / static_cast<double>(heading.size()));
    e.heading_max_deg = to_deg * *std::max_element(heading.begin(), heading.end());
    return e;
  }
};

}  // namespace

std::vector<map::Marker> rack_aisle_markers(const MarkerLocEvalParams& params) {
  std::vector<map::Marker> markers;
  for (int k = 0; k <= kBays; ++k) {
    const double x = kRackX0 + kPillarPitch * k;
    markers.push_back({100 + k, {x, params.south_face_y, std::numbers::pi / 2}, 1.0});
    markers.push_back({110 + k, {x, params.north_face_y, -std::numbers::pi / 2}, 1.0});
  }
  return markers;
}

MarkerLocEvalResult run_marker_loc_eval(const MarkerLocEvalParams& params) {
  if (!(params.duration > 0.0)) throw std::invalid_argument("marker loc-eval: duration must be > 0");
  if (!(params.speed > 0.0)) throw std::invalid_argument("marker loc-eval: speed must be > 0");
  const double south_lane = params.south_face_y + params.rack_distance;
  const double north_lane = params.north_face_y - params.rack_distance;
  if (!(north_lane >= south_lane)) {
    throw std::invalid_argument("marker loc-eval: rack_distance leaves no room between the rack faces");
  }
  const std::vector<map::Marker> site_markers = params.markers.empty() ? rack_aisle_markers(params) : params.markers;
  std::vector<perception::Marker> markers;
  for (const auto& m : site_markers) markers.push_back({m.id, m.pose});

  if (!params.route.empty() && params.route.size() < 2) {
    throw std::invalid_argument("marker loc-eval: a route needs at least two points");
  }
  const Pose2 start =
      params.route.empty()
          ? Pose2{params.x_from, south_lane, 0.0}
          : Pose2{params.route[0].x, params.route[0].y,
                  std::atan2(params.route[1].y - params.route[0].y, params.route[1].x - params.route[0].x)};
  sim::ForkliftParams body_params = sim::summit_xls_body_params();
  sim::ForkliftBody body(body_params, start, std::mt19937_64(params.seed));
  std::vector<geometry::Polygon> occluders = params.occluders;
  if (occluders.empty() && params.route.empty()) {
    constexpr double kRackDepth = 1.2;
    for (const double face : {params.south_face_y, params.north_face_y}) {
      const double back = face == params.south_face_y ? face - kRackDepth : face + kRackDepth;
      const double lo = std::min(face, back);
      const double hi = std::max(face, back);
      const double x1 = kRackX0 + kPillarPitch * kBays;
      occluders.push_back({{kRackX0, lo}, {x1, lo}, {x1, hi}, {kRackX0, hi}});
    }
  }
  localization::MarkerLocalizer localizer(params.localizer, body_params.mecanum, start, markers, occluders,
                                          std::mt19937_64(params.seed + 1));

  control::WaypointControllerParams cp;
  cp.max_speed = params.speed;
  control::WaypointController controller(cp);
  // One lap east along the south face, one west along the north face; the base turns on the spot at each end.
  // A route is driven to its end and back.
  std::vector<std::vector<Vec2>> legs{{{params.x_to, south_lane}, {params.x_to, north_lane}},
                                      {{params.x_from, north_lane}, {params.x_from, south_lane}}};
  if (!params.route.empty()) {
    legs = {std::vector<Vec2>(params.route.begin() + 1, params.route.end()),
            std::vector<Vec2>(params.route.rbegin() + 1, params.route.rend())};
  }
  std::size_t leg = 0;
  controller.set_waypoints(legs[0]);

  MarkerLocEvalResult r;
  ErrorSamples ekf_errors;
  ErrorSamples odometry_errors;
  Vec2 last_position = start.position();
  double worst = 0.0;
  const int steps = static_cast<int>(std::ceil(params.duration / kPeriod));
  for (int i = 1; i <= steps; ++i) {
    const double t = i * kPeriod;
    const control::BodyTwist cmd = controller.update(localizer.ekf().pose());
    body.step({cmd.vx, cmd.vy, cmd.omega}, kPeriod);
    localizer.step(t, kPeriod, {cmd.vx, cmd.vy, cmd.omega}, body.wheel_speeds(), body.pose(),
                   std::hypot(body.twist().vx, body.twist().vy), body.twist().omega);
    ekf_errors.add(body.pose(), localizer.ekf().pose());
    if (ekf_errors.position.back() >= worst) {
      worst = ekf_errors.position.back();
      r.worst_at = body.pose().position();
    }
    odometry_errors.add(body.pose(), localizer.odometry());
    r.distance_m += geometry::distance(body.pose().position(), last_position);
    last_position = body.pose().position();
    if (i % 25 == 0) {
      r.truth.push_back(body.pose());
      r.estimate.push_back(localizer.ekf().pose());
    }
    if (controller.done()) {
      ++r.laps;
      leg = 1 - leg;
      controller.set_waypoints(legs[leg]);
    }
  }
  r.sightings = localizer.sightings();
  r.sightings_fused = localizer.fused();
  r.sightings_gated = localizer.gated();
  r.longest_gap_s = std::max(localizer.longest_gap(), params.duration - localizer.last_fused());
  r.markers_seen = static_cast<int>(localizer.markers_seen().size());
  r.ekf = ekf_errors.summary();
  r.odometry = odometry_errors.summary();
  return r;
}

}  // namespace fleet::eval
