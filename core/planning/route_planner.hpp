#pragma once

#include <limits>
#include <vector>

#include "geometry/pose.hpp"
#include "planning/grid_planner.hpp"
#include "planning/road_planner.hpp"

namespace fleet::planning {

/// Fixed per RoutePlanner.
struct RoutePlannerConfiguration {
  /// A pose this close to its nearest graph point is on the road: no grid leg is planned.
  double on_graph_tolerance = 0.05;
  /// The route starts from the cheapest of the nearest graph point and the points it leads to
  /// that are at most this many times as far (RoadPlanner::start_states): between two points of
  /// a lane, the one ahead, not a hook back to the one behind.
  double start_slack = 1.25;
  /// Finite: the route ends on the road, at the nearest point of a lane along the goal's heading
  /// (either way) within this, rad, with no grid leg to the goal pose: a vehicle that cannot
  /// move sideways (a tricycle) starts its manoeuvre there, never from across a junction's
  /// connecting road.
  double goal_heading_tolerance = std::numeric_limits<double>::infinity();
};

struct Route {
  PlanStatus status = PlanStatus::kNoPath;
  std::vector<geometry::Vec2> points;  ///< start pose, grid leg, road points, grid leg, goal pose
  double length = 0.0;
  RoadPlan road;
  GridPath to_road;    ///< start pose to the first road point; empty when the start is on the road
  GridPath from_road;  ///< last road point to the goal pose; empty when the goal is on the road
};

/// Poses along a polyline, each heading along the leg that arrives at it (the first along the
/// first leg): what a path follower takes from a planner's points.
std::vector<geometry::Pose2> poses_along(const std::vector<geometry::Vec2>& points);

/// Road A* between the graph points nearest the poses, with grid legs where a pose lies off the
/// graph: from the road's end to a loading area and back (after [Forklift thesis, Fig. 5.1]).
/// The grid planner must hold the static grid (inflated). When the road plan is blocked
/// (Forklift thesis, Fig. 5.11) the route ends at the last free road point and no goal leg is planned.
class RoutePlanner {
 public:
  RoutePlanner(RoadPlanner& road, GridPlanner& grid, const RoutePlannerConfiguration& configuration = {});
  Route plan(const geometry::Pose2& start, const geometry::Pose2& goal, const PlanOptions& options = {});

 private:
  RoadPlanner& road_;
  GridPlanner& grid_;
  RoutePlannerConfiguration configuration_;
};

}  // namespace fleet::planning
