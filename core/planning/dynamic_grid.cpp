#include "planning/dynamic_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fleet::planning {

double distance_since_seen(double speed, double age, double stale_after, double max_speed) {
  const double a = std::max(0.0, age);
  return std::abs(speed) * std::min(a, stale_after) + max_speed * std::max(0.0, a - stale_after);
}

DynamicGrid::DynamicGrid(const DynamicGridConfiguration& configuration) : configuration_(configuration) {
  if (configuration.own_radius < 0.0 || configuration.safety_margin < 0.0 || configuration.max_speed < 0.0 ||
      configuration.stale_after < 0.0 || configuration.max_reach < 0.0) {
    throw std::invalid_argument("dynamic grid: radii, margin, speeds and times must be >= 0");
  }
  if (!(configuration.reported_tolerance >= 0.0)) {
    throw std::invalid_argument("dynamic grid: reported_tolerance must be >= 0");
  }
}

geometry::Polygon DynamicGrid::occupied_region(const Neighbour& n) const {
  const double moved = distance_since_seen(n.speed, n.age, configuration_.stale_after, configuration_.max_speed);
  return geometry::footprint_polygon(n.pose, n.footprint,
                                     configuration_.safety_margin + std::min(configuration_.max_reach, moved));
}

void DynamicGrid::update(const OccupancyGrid& static_grid, std::span<const Neighbour> neighbours,
                         const OccupancyGrid* sensed) {
  if (sensed != nullptr && !sensed->same_geometry(static_grid)) {
    throw std::invalid_argument("dynamic grid: sensed layer and static grid differ in geometry");
  }
  // Ten times a second over the whole site: the grids keep their storage from one update to the
  // next (copies into a grid of the same size allocate nothing).
  if (sensed != nullptr) {
    dynamic_ = *sensed;
  } else if (dynamic_.same_geometry(static_grid)) {
    dynamic_.clear();
  } else {
    dynamic_ = OccupancyGrid(static_grid.bounds(), static_grid.resolution(), OccupancyGrid::kFree);
  }
  if (sensed != nullptr && configuration_.reported_tolerance > 0.0) {
    for (const Neighbour& n : neighbours) {
      dynamic_.fill_polygon(geometry::footprint_polygon(n.pose, n.footprint, configuration_.reported_tolerance), false);
    }
  }
  for (const Neighbour& n : neighbours) dynamic_.fill_polygon(occupied_region(n), true);
  // Grow everything by our own radius: the path is then checked as a line of points.
  dynamic_.dilate(configuration_.own_radius);
  static_grid_ = &static_grid;
  grid_current_ = false;
}

const OccupancyGrid& DynamicGrid::grid() const {
  if (!grid_current_ && static_grid_ != nullptr) {
    grid_.assign_union(*static_grid_, dynamic_);
    grid_current_ = true;
  }
  return grid_;
}

}  // namespace fleet::planning
