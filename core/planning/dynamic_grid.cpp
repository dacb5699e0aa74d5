#include "planning/dynamic_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace fleet::planning {

DynamicGrid::DynamicGrid(const DynamicGridConfiguration& configuration) : configuration_(configuration) {
  if (configuration.own_radius < 0.0 || configuration.safety_margin < 0.0 || configuration.max_speed < 0.0 ||
      configuration.stale_after < 0.0 || configuration.max_reach < 0.0) {
    throw std::invalid_argument("dynamic grid: radii, margin, speeds and times must be >= 0");
  }
}

geometry::Polygon DynamicGrid::occupied_region(const Neighbour& n) const {
  const double age = std::max(0.0, n.age);
  if (is_stale(n)) {
    const double body = std::hypot(n.footprint.length, n.footprint.width) / 2.0;
    const double r =
        body + configuration_.safety_margin + std::min(configuration_.max_reach, configuration_.max_speed * age);
    // Circumscribed 16-gon, so the polygon contains the whole disc.
    constexpr int k = 16;
    const double rc = r / std::cos(std::numbers::pi / k);
    geometry::Polygon p;
    for (int i = 0; i < k; ++i) {
      const double a = 2.0 * std::numbers::pi * i / k;
      p.push_back({n.pose.x + rc * std::cos(a), n.pose.y + rc * std::sin(a)});
    }
    return p;
  }
  const double grow = configuration_.safety_margin + std::abs(n.speed) * age;
  return geometry::footprint_polygon(n.pose, n.footprint, grow);
}

void DynamicGrid::update(const OccupancyGrid& static_grid, std::span<const Neighbour> neighbours,
                         const OccupancyGrid* sensed) {
  if (sensed != nullptr && !sensed->same_geometry(static_grid)) {
    throw std::invalid_argument("dynamic grid: sensed layer and static grid differ in geometry");
  }
  OccupancyGrid raw(static_grid.bounds(), static_grid.resolution(), OccupancyGrid::kFree);
  if (sensed != nullptr) raw = *sensed;
  for (const Neighbour& n : neighbours) raw.fill_polygon(occupied_region(n), true);
  // Grow everything by our own radius: the path is then checked as a line of points.
  dynamic_ = raw.dilated(configuration_.own_radius);
  grid_ = static_grid;
  grid_.merge_occupied(dynamic_);
}

}  // namespace fleet::planning
