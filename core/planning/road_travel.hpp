#pragma once
// How far a vehicle drives on the road graph between two poses, for whoever estimates travel
// without driving it (dispatch costs, cycle-time evaluations).

#include "geometry/pose.hpp"
#include "planning/road_planner.hpp"

namespace fleet::planning {

/// Metres driven from `from` to `to` on `planner`'s graph: from `from` onto the route's first
/// point, the route [Forklift thesis, section 5.2], and from its last point to `to`; +infinity
/// when the planner finds no route.
double road_travel_distance(RoadPlanner& planner, const geometry::Pose2& from, const geometry::Pose2& to);

}  // namespace fleet::planning
