#pragma once

#include <memory>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "planning/occupancy_grid.hpp"
#include "planning/plan_status.hpp"

namespace fleet::planning {

struct GridPath {
  PlanStatus status = PlanStatus::kNoPath;
  std::vector<geometry::Vec2> points;  ///< from the start to the goal, straight segments between
  double length = 0.0;                 ///< metres
  std::size_t expanded = 0;            ///< search nodes expanded (or OMPL tree vertices)
};

/// A planner for a point robot on an occupancy grid already inflated by the robot's size
/// (STYLE 4-7): bounded by `PlanOptions::node_cap` and `time_budget`, interruptible through
/// `PlanOptions::cancel`, with the outcome as a status.
///
/// Thread safety: an instance serves one query at a time; separate instances are independent.
class GridPlanner {
 public:
  virtual ~GridPlanner() = default;
  /// Short, stable name used in reports, e.g. "grid_astar".
  virtual std::string name() const = 0;
  /// The grid to plan on; kept alive by the planner. Planners may precompute on it here.
  virtual void set_grid(std::shared_ptr<const OccupancyGrid> grid) = 0;
  virtual GridPath plan(geometry::Vec2 start, geometry::Vec2 goal, const PlanOptions& options) = 0;
};

double path_length(const std::vector<geometry::Vec2>& points);

}  // namespace fleet::planning
