#include "planning/route_planner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace fleet::planning {

using geometry::Vec2;

namespace {

void append(std::vector<Vec2>& out, const std::vector<Vec2>& more) {
  for (const Vec2& p : more) {
    if (out.empty() || geometry::distance(out.back(), p) > 1e-9) out.push_back(p);
  }
}

/// What is left of the caller's budget, for the next leg.
PlanOptions remaining(const PlanOptions& options, const Deadline& deadline) {
  PlanOptions o = options;
  const auto left = std::chrono::duration_cast<std::chrono::microseconds>(deadline.end() - Deadline::Clock::now());
  o.time_budget = left.count() > 0 ? left : std::chrono::microseconds(0);
  return o;
}

}  // namespace

std::vector<geometry::Pose2> poses_along(const std::vector<geometry::Vec2>& points) {
  std::vector<geometry::Pose2> poses;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const geometry::Vec2 a = points[i == 0 ? 0 : i - 1];
    const geometry::Vec2 b = points[i == 0 ? std::min<std::size_t>(1, points.size() - 1) : i];
    const double yaw = geometry::distance(a, b) > 1e-9 ? std::atan2(b.y - a.y, b.x - a.x) : 0.0;
    poses.push_back({points[i].x, points[i].y, yaw});
  }
  if (poses.size() >= 2) poses.front().yaw = poses[1].yaw;
  return poses;
}

RoutePlanner::RoutePlanner(RoadPlanner& road, GridPlanner& grid, const RoutePlannerConfiguration& configuration)
    : road_(road), grid_(grid), configuration_(configuration) {}

Route RoutePlanner::plan(const geometry::Pose2& start, const geometry::Pose2& goal, const PlanOptions& options) {
  Route route;
  const Deadline deadline(options);
  const auto starts = road_.start_states(start.position(), configuration_.start_slack);
  const int s = starts.empty() ? -1 : starts.front().first;
  const bool on_road = std::isfinite(configuration_.goal_heading_tolerance);
  const int g = on_road ? road_.nearest_point_along(goal.position(), goal.yaw, configuration_.goal_heading_tolerance)
                        : road_.nearest_point(goal.position(), RoadPlanner::PointUse::kRoute);
  if (s < 0 || g < 0) {
    route.status = PlanStatus::kInvalidStart;
    return route;
  }
  route.road = road_.plan_from(starts, g, remaining(options, deadline));
  if (route.road.status != PlanStatus::kFound && route.road.status != PlanStatus::kBlockedPartial) {
    route.status = route.road.status;
    return route;
  }
  const Vec2 first = route.road.points.front();
  route.points.push_back(start.position());
  if (geometry::distance(start.position(), first) > configuration_.on_graph_tolerance) {
    route.to_road = grid_.plan(start.position(), first, remaining(options, deadline));
    if (route.to_road.status == PlanStatus::kInvalidStart) {
      // The robot stands where its map has no free space: a map switch took away the road under
      // it. It drives straight onto the road point its road plan starts from (the nearest, or
      // one beside it: start_states), its own safety check watching as always.
      route.to_road = {PlanStatus::kFound, {start.position(), first}, geometry::distance(start.position(), first), 0};
    }
    if (route.to_road.status != PlanStatus::kFound) {
      route.status = route.to_road.status;
      route.points.clear();
      return route;
    }
    append(route.points, route.to_road.points);
  }
  append(route.points, route.road.points);
  route.status = route.road.status;
  if (route.road.status == PlanStatus::kFound && !on_road &&
      geometry::distance(goal.position(), route.road.points.back()) > configuration_.on_graph_tolerance) {
    route.from_road = grid_.plan(route.road.points.back(), goal.position(), remaining(options, deadline));
    if (route.from_road.status != PlanStatus::kFound) {
      // The road part stands; the robot can drive it while the last leg is retried.
      route.status = route.from_road.status;
    } else {
      append(route.points, route.from_road.points);
    }
  }
  route.length = path_length(route.points);
  return route;
}

}  // namespace fleet::planning
