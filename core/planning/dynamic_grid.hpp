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
  double stale_after = 0.5;     ///< s; beyond it a neighbour may have sped up to max_speed
  double max_speed = 0.5;       ///< m/s a robot can reach; bounds where a stale one may be
  double max_reach = 3.0;       ///< metres; caps how far a neighbour's body grows
  /// Metres round a neighbour's reported footprint within which the sensed layer is taken to be
  /// that neighbour, and left to its report (0: the sensed layer is kept whole).
  double reported_tolerance = 0.0;
};

/// How far a robot last seen `age` seconds ago at `speed` may have moved since: at the speed it
/// reported for as long as its data counts as fresh (`stale_after`), at up to `max_speed` beyond.
/// It grows with the age without a jump, so a message a little late (a loaded host, a high time
/// scale) grows a body by the little it may have moved, not by a whole age at top speed: a
/// standing robot grown by a metre for a late message stops its neighbours for good.
double distance_since_seen(double speed, double age, double stale_after, double max_speed);

/// The dynamic occupancy grid [Forklift thesis, section 5.3]: the static grid plus the other robots
/// and what the lidar sees, all grown by our robot's radius so a path point is checked as a point.
///
/// A neighbour is judged by its report, not by how the lidar saw it: the OctoMap holds the scans
/// filed under where the robot believed it was at each, so a body seen from a drifting estimate
/// lies smeared over cells beside it. Sensed cells within `reported_tolerance` of a neighbour's
/// reported footprint are cleared before the neighbours are drawn; the reports are what traffic
/// keeps apart, and the sensed layer still holds everything nobody reports.
///
/// Neighbours occupy their footprint grown by the margin and by how far they may have moved since
/// their pose was measured (distance_since_seen, capped at `max_reach`): stale data slows us,
/// never lets us drive into them. Every point of a body moves at most `max_speed` (a turn on the
/// spot too), so the grown footprint holds wherever the body may be by now.
class DynamicGrid {
 public:
  explicit DynamicGrid(const DynamicGridConfiguration& configuration = {});

  /// Rebuilds both layers. `sensed` (the projected OctoMap, may be null) must share the static
  /// grid's geometry.
  void update(const OccupancyGrid& static_grid, std::span<const Neighbour> neighbours, const OccupancyGrid* sensed);

  /// Static + dynamic: what local planning checks the path against. Made on the first call after
  /// an update, from the static grid that update was given (which must still be alive): the
  /// robots read only the dynamic layer, and a whole-site union ten times a second cost them a
  /// fifth of their time.
  const OccupancyGrid& grid() const;
  /// The dynamic part alone (neighbours and sensed obstacles, grown): where "seen free" is read.
  const OccupancyGrid& dynamic_layer() const { return dynamic_; }
  const DynamicGridConfiguration& configuration() const { return configuration_; }

  /// The region a neighbour occupies under the rules above (exposed for tests and the web view).
  geometry::Polygon occupied_region(const Neighbour& n) const;
  bool is_stale(const Neighbour& n) const { return n.age > configuration_.stale_after; }

 private:
  DynamicGridConfiguration configuration_;
  OccupancyGrid dynamic_;
  const OccupancyGrid* static_grid_ = nullptr;
  mutable OccupancyGrid grid_;
  mutable bool grid_current_ = false;
};

}  // namespace fleet::planning
