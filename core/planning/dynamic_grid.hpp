#pragma once

#include <span>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"
#include "planning/occupancy_grid.hpp"

namespace fleet::planning {

/// Another robot as FleetView reports it.
struct Neighbour {
  std::string id;
  geometry::Pose2 pose;
  double speed = 0.0;  ///< m/s, magnitude
  double age = 0.0;    ///< seconds since the pose was measured
  geometry::Footprint footprint;
};

/// Fixed per DynamicGrid.
struct DynamicGridConfiguration {
  double own_radius = 0.15;     ///< our robot's circumscribed radius: obstacles grow by it
  double safety_margin = 0.05;  ///< metres added around every other robot
  double stale_after = 0.5;     ///< s; older neighbour data means "anywhere it could be"
  double max_speed = 0.5;       ///< m/s a robot can reach; bounds where a stale one may be
  double max_reach = 3.0;       ///< metres; caps a stale neighbour's disc
};

/// The dynamic occupancy grid [Forklift thesis, section 5.3]: the static grid plus the other robots
/// and what the lidar sees, all grown by our robot's radius so a path point is checked as a point.
///
/// Fresh neighbours occupy their footprint grown by the margin and by speed x data age (how far
/// the robot may have moved since); a neighbour older than `stale_after` occupies the disc of
/// everywhere it could have reached at `max_speed`, so stale data slows us, never lets us drive
/// into it.
class DynamicGrid {
 public:
  explicit DynamicGrid(const DynamicGridConfiguration& configuration = {});

  /// Rebuilds both layers. `sensed` (the projected OctoMap, may be null) must share the static
  /// grid's geometry.
  void update(const OccupancyGrid& static_grid, std::span<const Neighbour> neighbours, const OccupancyGrid* sensed);

  /// Static + dynamic: what local planning checks the path against.
  const OccupancyGrid& grid() const { return grid_; }
  /// The dynamic part alone (neighbours and sensed obstacles, grown): where "seen free" is read.
  const OccupancyGrid& dynamic_layer() const { return dynamic_; }
  const DynamicGridConfiguration& configuration() const { return configuration_; }

  /// The region a neighbour occupies under the rules above (exposed for tests and the web view).
  /// A stale neighbour gives a polygon approximating its disc.
  geometry::Polygon occupied_region(const Neighbour& n) const;
  bool is_stale(const Neighbour& n) const { return n.age > configuration_.stale_after; }

 private:
  DynamicGridConfiguration configuration_;
  OccupancyGrid dynamic_;
  OccupancyGrid grid_;
};

}  // namespace fleet::planning
