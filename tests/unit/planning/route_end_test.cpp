// A route for a vehicle that cannot step sideways ends on the lane along the goal's heading, not
// on a connecting road that happens to pass nearer the goal, and with no grid leg off the road.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "planning/grid_astar.hpp"
#include "planning/route_planner.hpp"

namespace fleet::planning {
namespace {

int add_point(map::RoadGraph& g, double x, double y) {
  map::GraphPoint p;
  p.id = static_cast<int>(g.points.size());
  p.x = x;
  p.y = y;
  g.points.push_back(p);
  g.successors.emplace_back();
  return p.id;
}

void link(map::RoadGraph& g, int a, int b) {
  g.successors[static_cast<std::size_t>(a)].push_back(b);
  g.successors[static_cast<std::size_t>(b)].push_back(a);
}

// A lane along y = 0 from x = 0 to 10, and a connecting road leaving it at x = 4 diagonally down
// to (5, -1) and on to (5, -3), every point 0.25 m or so apart.
map::RoadGraph lane_with_connecting_road() {
  map::RoadGraph g;
  int prev = -1, at_four = -1;
  for (int i = 0; i <= 40; ++i) {
    const int p = add_point(g, 0.25 * i, 0.0);
    if (prev >= 0) link(g, prev, p);
    if (i == 16) at_four = p;
    prev = p;
  }
  prev = at_four;
  for (int i = 1; i <= 4; ++i) {
    const int p = add_point(g, 4.0 + 0.25 * i, -0.25 * i);
    link(g, prev, p);
    prev = p;
  }
  for (int i = 1; i <= 8; ++i) {
    const int p = add_point(g, 5.0, -1.0 - 0.25 * i);
    link(g, prev, p);
    prev = p;
  }
  return g;
}

TEST(RouteEnd, OnTheLaneAlongTheGoalsHeadingWithoutAGridLeg) {
  const map::RoadGraph g = lane_with_connecting_road();
  RoadPlanner road(g);
  GridAStar astar;
  astar.set_grid(std::make_shared<const OccupancyGrid>(geometry::Bounds{-1.0, -4.0, 11.0, 2.0}, 0.05));
  // The goal beside the connecting road, heading along the lane (either way).
  const geometry::Pose2 start{0.0, 0.0, 0.0};
  const geometry::Pose2 goal{4.8, -0.6, std::numbers::pi};
  const int nearest = road.nearest_point(goal.position());
  ASSERT_LT(g.points[static_cast<std::size_t>(nearest)].y, -0.1) << "the connecting road passes nearer the goal";

  const int along = road.nearest_point_along(goal.position(), goal.yaw, 0.35);
  ASSERT_GE(along, 0);
  EXPECT_NEAR(g.points[static_cast<std::size_t>(along)].y, 0.0, 1e-9);
  EXPECT_NEAR(g.points[static_cast<std::size_t>(along)].x, 4.75, 1e-9);

  RoutePlanner tricycle(road, astar, {.goal_heading_tolerance = 0.35});
  const Route r = tricycle.plan(start, goal);
  ASSERT_EQ(r.status, PlanStatus::kFound);
  EXPECT_TRUE(r.from_road.points.empty());
  EXPECT_NEAR(r.points.back().x, 4.75, 1e-9);
  EXPECT_NEAR(r.points.back().y, 0.0, 1e-9);
  for (const auto& p : r.points) EXPECT_NEAR(p.y, 0.0, 1e-9) << "the route leaves the lane at x = " << p.x;

  // Without the heading, the route turns onto the connecting road and leaves it for the goal.
  RoutePlanner omni(road, astar);
  const Route o = omni.plan(start, goal);
  ASSERT_EQ(o.status, PlanStatus::kFound);
  EXPECT_NEAR(geometry::distance(o.points.back(), goal.position()), 0.0, 1e-9);
  EXPECT_FALSE(o.from_road.points.empty());
}

TEST(RouteEnd, NoLaneAlongTheHeadingIsNoStart) {
  const map::RoadGraph g = lane_with_connecting_road();
  RoadPlanner road(g);
  // Every lane runs along x, down the connecting road, or diagonally: none at 60 degrees.
  EXPECT_EQ(road.nearest_point_along({4.8, -0.6}, std::numbers::pi / 3, 0.2), -1);
}

}  // namespace
}  // namespace fleet::planning
