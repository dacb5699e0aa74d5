#include "planning/lidar_sim.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace fleet::planning {

using geometry::Vec2;

LidarSim::LidarSim(const LidarConfiguration& configuration) : configuration_(configuration) {
  if (configuration.beams <= 0) throw std::invalid_argument("lidar: beams must be positive");
  if (!(configuration.max_range > 0.0)) throw std::invalid_argument("lidar: max_range must be positive");
}

LidarScan LidarSim::scan(const geometry::Pose2& pose, std::span<const geometry::Polygon> polygons) const {
  LidarScan out;
  out.pose = pose;
  out.max_range = configuration_.max_range;
  out.angle_min = -std::numbers::pi;
  out.angle_increment = 2.0 * std::numbers::pi / configuration_.beams;
  out.ranges.assign(static_cast<std::size_t>(configuration_.beams), std::numeric_limits<double>::infinity());
  const Vec2 o = pose.position();
  const double r = configuration_.max_range;

  // Only edges that can be within range matter: cull by the polygons' bounding boxes.
  std::vector<std::pair<Vec2, Vec2>> edges;
  for (const auto& poly : polygons) {
    if (poly.size() < 2) continue;
    const geometry::Bounds b = geometry::bounding_box(poly);
    const double dx = std::max({b.min_x - o.x, 0.0, o.x - b.max_x});
    const double dy = std::max({b.min_y - o.y, 0.0, o.y - b.max_y});
    if (dx * dx + dy * dy > r * r) continue;
    for (std::size_t i = 0; i < poly.size(); ++i) edges.emplace_back(poly[i] - o, poly[(i + 1) % poly.size()] - o);
  }
  for (int i = 0; i < configuration_.beams; ++i) {
    const double a = pose.yaw + out.angle_min + i * out.angle_increment;
    const Vec2 d{std::cos(a), std::sin(a)};
    double best = std::numeric_limits<double>::infinity();
    for (const auto& [p, q] : edges) {
      // Ray o + t d against segment p + u (q - p): solve with 2D cross products.
      const Vec2 e = q - p;
      const double den = geometry::cross(d, e);
      if (std::abs(den) < 1e-12) continue;
      const double t = geometry::cross(p, e) / den;
      const double u = geometry::cross(p, d) / den;
      if (t >= configuration_.min_range && u >= 0.0 && u <= 1.0 && t < best) best = t;
    }
    if (best <= r) out.ranges[static_cast<std::size_t>(i)] = best;
  }
  return out;
}

}  // namespace fleet::planning
