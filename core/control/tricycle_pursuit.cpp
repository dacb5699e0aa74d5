#include "control/tricycle_pursuit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleet::control {

namespace {

struct Projection {
  std::size_t segment = 0;
  double along = 0.0;      ///< path length from the start to the projection, m
  double remaining = 0.0;  ///< path length from the projection to the end, m
};

Projection project(const std::vector<geometry::Vec2>& path, geometry::Vec2 p) {
  Projection best;
  double best_distance = std::numeric_limits<double>::infinity();
  double cumulative = 0.0;
  double total = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const geometry::Vec2 ab = path[i + 1] - path[i];
    total += std::sqrt(geometry::dot(ab, ab));
  }
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const geometry::Vec2 ab = path[i + 1] - path[i];
    const double len2 = geometry::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(geometry::dot(p - path[i], ab) / len2, 0.0, 1.0) : 0.0;
    const geometry::Vec2 pq = p - (path[i] + t * ab);
    const double d = std::sqrt(geometry::dot(pq, pq));
    if (d < best_distance - 1e-9) {
      best_distance = d;
      best.segment = i;
      best.along = cumulative + t * std::sqrt(len2);
    }
    cumulative += std::sqrt(len2);
  }
  best.remaining = total - best.along;
  return best;
}

geometry::Vec2 point_at(const std::vector<geometry::Vec2>& path, double s) {
  double cumulative = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double len = geometry::distance(path[i], path[i + 1]);
    if (cumulative + len >= s && len > 0.0) return path[i] + ((s - cumulative) / len) * (path[i + 1] - path[i]);
    cumulative += len;
  }
  return path.back();
}

}  // namespace

TricyclePursuitOutput pursue(const geometry::Pose2& rear, const std::vector<geometry::Vec2>& path, double room,
                             double steer_angle, const TricyclePursuitParams& params, double wheelbase) {
  TricyclePursuitOutput out;
  out.command.theta_steer = steer_angle;
  if (path.size() < 2) {
    out.arrived = true;
    return out;
  }
  const Projection here = project(path, rear.position());
  out.remaining = here.remaining - params.stop_short;
  const double to_end = geometry::distance(rear.position(), path.back()) - params.stop_short;
  if (out.remaining <= params.arrive_tolerance || to_end <= params.arrive_tolerance) {
    out.arrived = true;
    return out;
  }
  // Past the path's end the lookahead stays on its end point: pure pursuit then aims at it.
  const geometry::Vec2 target = point_at(path, here.along + params.lookahead);
  const geometry::Vec2 local = geometry::map_to_body(rear, target);
  const double bearing = std::atan2(local.y, local.x);
  // Held (no room granted, or none clear): it stands, not even pivoting, as its front sweeps far
  // round the rear axle into places traffic has not granted it.
  if (room <= 0.0) return out;
  if (std::abs(bearing) > params.pivot_above) {
    // The route leads off behind or beside the stacker: turn about the rear axle first [Stacker
    // thesis, section 5.2], theta_steer = +-pi/2.
    out.command = sim::inverse_kinematics({0.0, std::copysign(params.pivot_yaw_rate, bearing)}, wheelbase);
    if (std::abs(geometry::angle_diff(out.command.theta_steer, steer_angle)) > 0.1) out.command.v_steer = 0.0;
    return out;
  }
  const double distance = std::hypot(local.x, local.y);
  const double curvature = 2.0 * local.y / std::max(distance * distance, 1e-6);
  double v = params.max_speed;
  v = std::min(v, std::sqrt(params.lateral_acceleration / std::max(std::abs(curvature), 1e-6)));
  const double stop_within = std::min(out.remaining - 0.5 * params.arrive_tolerance, room);
  v = std::min(v, std::sqrt(2.0 * params.acceleration * std::max(stop_within, 0.0)));
  if (stop_within > 0.0) v = std::max(v, std::min(params.creep_speed, stop_within));
  if (stop_within <= 0.0) return out;
  out.command = sim::inverse_kinematics({v, v * curvature}, wheelbase);
  // The wheel rolls once it points about where it is asked to.
  if (std::abs(geometry::angle_diff(out.command.theta_steer, steer_angle)) > 0.35) out.command.v_steer = 0.0;
  return out;
}

}  // namespace fleet::control
