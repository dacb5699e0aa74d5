#include "planning/road_planner.hpp"

#include <gtest/gtest.h>

#include <limits>
#include <queue>
#include <random>

#include "planning/road_travel.hpp"
#include "planning/static_grid.hpp"
#include "test_graphs.hpp"

namespace fleet::planning {
namespace {

using testing::lattice_graph;
using testing::site_for;
using testing::square;

// Textbook Dijkstra on distances, the optimum A* with w_h = 0 must reach.
double dijkstra(const map::RoadGraph& g, int s, int t) {
  std::vector<double> dist(g.points.size(), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  dist[s] = 0.0;
  q.push({0.0, s});
  while (!q.empty()) {
    auto [d, u] = q.top();
    q.pop();
    if (d > dist[u]) continue;
    for (int v : g.successors[u]) {
      const double nd = d + std::hypot(g.points[v].x - g.points[u].x, g.points[v].y - g.points[u].y);
      if (nd < dist[v]) {
        dist[v] = nd;
        q.push({nd, v});
      }
    }
  }
  return dist[t];
}

map::RoadGraph random_graph(std::mt19937& rng, int n, int extra_edges) {
  map::RoadGraph g;
  std::uniform_real_distribution<double> coord(0.0, 10.0);
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int i = 0; i < n; ++i) {
    map::GraphPoint p;
    p.id = i;
    p.x = coord(rng);
    p.y = coord(rng);
    g.points.push_back(p);
  }
  g.successors.resize(n);
  // A random spanning tree keeps most of the graph connected; extra directed edges add choice.
  for (int i = 1; i < n; ++i) {
    const int j = std::uniform_int_distribution<int>(0, i - 1)(rng);
    g.successors[i].push_back(j);
    g.successors[j].push_back(i);
  }
  for (int k = 0; k < extra_edges; ++k) {
    const int a = pick(rng);
    const int b = pick(rng);
    if (a != b) g.successors[a].push_back(b);
  }
  return g;
}

TEST(RoadPlanner, MatchesDijkstraOnRandomGraphsWithoutHeadingCost) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const map::RoadGraph g = random_graph(rng, 60 + trial * 5, 150);
    RoadPlanner planner(g, {.w_d = 1.0, .w_h = 0.0, .obstacle_cost = 100.0});
    std::uniform_int_distribution<int> pick(0, static_cast<int>(g.points.size()) - 1);
    for (int q = 0; q < 20; ++q) {
      const int s = pick(rng);
      const int t = pick(rng);
      const double best = dijkstra(g, s, t);
      const RoadPlan plan = planner.plan_between(s, t, 0.0);
      ASSERT_EQ(plan.status, PlanStatus::kFound);
      EXPECT_NEAR(plan.cost, best, 1e-9) << "trial " << trial << " query " << q;
      EXPECT_NEAR(plan.length, best, 1e-9);
      ASSERT_EQ(plan.point_ids.front(), s);
      ASSERT_EQ(plan.point_ids.back(), t);
      for (std::size_t k = 1; k < plan.point_ids.size(); ++k) {
        const auto& succ = g.successors[plan.point_ids[k - 1]];
        EXPECT_NE(std::find(succ.begin(), succ.end(), plan.point_ids[k]), succ.end()) << "not an edge";
      }
    }
  }
}

TEST(RoadPlanner, StartCostIsDistanceFromStartPose) {
  const map::RoadGraph g = lattice_graph(2, 1, 1.0, 0.1);
  RoadPlanner planner(g, {.w_d = 1.0, .w_h = 0.0});
  const RoadPlan plan = planner.plan({0.3, 0.5, 0.0}, {1.3, 0.3, 0.0});
  ASSERT_EQ(plan.status, PlanStatus::kFound);
  EXPECT_EQ(plan.point_ids.front(), planner.nearest_point({0.3, 0.3}));
  EXPECT_NEAR(plan.cost, 0.2 + 1.0, 1e-9);
}

TEST(RoadPlanner, BetweenTwoPointsOfALaneTheRouteStartsOnTheOneAhead) {
  // A lane driven east with points every 0.5 m. A robot that stands a little nearer the point
  // behind it (as a forklift backing out of a drop place onto the lane does) starts on the one
  // ahead: a route from the one behind would turn it round towards whatever stands there.
  map::RoadGraph g;
  for (int i = 0; i <= 8; ++i) {
    map::GraphPoint p;
    p.id = i;
    p.x = 0.5 * i;
    g.points.push_back(p);
    g.successors.push_back({(i + 1) % 9});  // the last point leads back to the first: one loop
  }
  RoadPlanner planner(g);
  const geometry::Vec2 here{1.24, 0.15};
  ASSERT_EQ(planner.nearest_point(here), 2);
  const auto starts = planner.start_states(here, 1.25);
  ASSERT_EQ(starts.size(), 2u);
  EXPECT_EQ(starts[1].first, 3);
  const RoadPlan plan = planner.plan_from(starts, 8);
  ASSERT_EQ(plan.status, PlanStatus::kFound);
  EXPECT_EQ(plan.point_ids.front(), 3);
  // Nearer the point behind by more than the slack, it starts there.
  EXPECT_EQ(planner.start_states({1.1, 0.15}, 1.25).size(), 1u);
  // The point ahead is no start when the lane runs the other way.
  for (int i = 0; i <= 8; ++i) g.successors[static_cast<std::size_t>(i)] = {(i + 8) % 9};
  RoadPlanner westward(g);
  const auto west_starts = westward.start_states(here, 1.25);
  for (const auto& [point, cost] : west_starts) EXPECT_LE(g.points[static_cast<std::size_t>(point)].x, 1.0 + 1e-9);
}

TEST(RoadPlanner, UnreachableGoalIsNoPath) {
  map::RoadGraph g = lattice_graph(2, 1, 1.0, 0.1);
  map::GraphPoint lone;
  lone.id = static_cast<int>(g.points.size());
  lone.x = 5.0;
  g.points.push_back(lone);
  g.successors.emplace_back();
  RoadPlanner planner(g);
  EXPECT_EQ(planner.plan_between(0, lone.id, 0.0).status, PlanStatus::kNoPath);
}

// Two equally long routes from (0,0) to (2,2) in a grid of 1 m cells: an L with one turn, and a
// staircase with three. The heading term of eq. 5.5 must pick the L.
TEST(RoadPlanner, HeadingCostPrefersStraightOverZigZag) {
  const map::RoadGraph g = lattice_graph(3, 3, 1.0, 0.5, 0.0, 0.0);
  RoadPlanner planner(g, {.w_d = 1.0, .w_h = 0.5});
  const int s = planner.nearest_point({0.0, 0.0});
  const int t = planner.nearest_point({2.0, 2.0});
  const RoadPlan plan = planner.plan_between(s, t, 0.0);
  ASSERT_EQ(plan.status, PlanStatus::kFound);
  EXPECT_NEAR(plan.length, 4.0, 1e-9);
  int turns = 0;
  for (std::size_t k = 2; k < plan.points.size(); ++k) {
    const auto a = plan.points[k - 1] - plan.points[k - 2];
    const auto b = plan.points[k] - plan.points[k - 1];
    if (std::abs(geometry::cross(a, b)) > 1e-9) ++turns;
  }
  EXPECT_EQ(turns, 1);
  EXPECT_NEAR(plan.cost, 4.0 + 0.5 * std::numbers::pi / 2.0, 1e-9);

  // Without the heading term the same query may zig-zag; its cost is the bare length.
  RoadPlanner plain(g, {.w_d = 1.0, .w_h = 0.0});
  EXPECT_NEAR(plain.plan_between(s, t, 0.0).cost, 4.0, 1e-9);
}

TEST(RoadPlanner, PrefersFreeDetourOverObstacle) {
  // Ring of roads: an obstacle on the short side sends the route round the long side.
  const map::RoadGraph g = lattice_graph(2, 2, 1.0, 0.1);
  const map::Site site = site_for(g);
  StaticGrid grid({.resolution = 0.02}, site, g);
  grid.add_obstacle("block", square(0.8, 0.3, 0.2));
  RoadPlanner planner(g);
  planner.set_obstacles(grid.grid());
  const RoadPlan plan = planner.plan({0.3, 0.3, 0.0}, {1.3, 0.3, 0.0});
  ASSERT_EQ(plan.status, PlanStatus::kFound);
  EXPECT_NEAR(plan.length, 3.0, 1e-9);
  for (int id : plan.point_ids) EXPECT_FALSE(planner.blocked(id));
}

TEST(RoadPlanner, BlockedRouteStopsBeforeObstacleAndResumesWhenRemoved) {
  // A single straight road 2 m long; an obstacle in the middle blocks every route (Fig. 5.11).
  const map::RoadGraph g = lattice_graph(3, 1, 1.0, 0.1);
  map::Site site = site_for(g);
  map::StaticObstacle o;
  o.id = "O1";
  o.polygon = square(1.3, 0.3, 0.2);
  site.static_obstacles.push_back(o);
  StaticGrid grid({.resolution = 0.02}, site, g);
  RoadPlanner planner(g);
  ASSERT_TRUE(grid.set_obstacle_enabled("O1", true));
  planner.set_obstacles(grid.grid());

  const RoadPlan blocked = planner.plan({0.3, 0.3, 0.0}, {2.3, 0.3, 0.0});
  ASSERT_EQ(blocked.status, PlanStatus::kBlockedPartial);
  ASSERT_FALSE(blocked.points.empty());
  for (int id : blocked.point_ids) EXPECT_FALSE(planner.blocked(id));
  // The plan ends at the last free point: the next point along the road is inside the obstacle.
  EXPECT_NEAR(blocked.points.back().x, 1.1, 1e-9);  // points every 0.1 m; the obstacle spans 1.2-1.4
  EXPECT_TRUE(planner.blocked(blocked.blocked_point));

  const auto rev = grid.revision();
  ASSERT_TRUE(grid.set_obstacle_enabled("O1", false));
  EXPECT_GT(grid.revision(), rev);
  planner.set_obstacles(grid.grid());
  const RoadPlan free = planner.plan({0.3, 0.3, 0.0}, {2.3, 0.3, 0.0});
  ASSERT_EQ(free.status, PlanStatus::kFound);
  EXPECT_NEAR(free.points.back().x, 2.3, 1e-9);
}

TEST(RoadPlanner, HonoursCancelFlagAndNodeCap) {
  std::mt19937 rng(3);
  const map::RoadGraph g = random_graph(rng, 3000, 3000);
  RoadPlanner planner(g);
  std::atomic<bool> cancel{true};
  PlanOptions options;
  options.cancel = &cancel;
  // The flag is polled every few dozen expansions; a far query expands more than that.
  const int s = planner.nearest_point({0.0, 0.0});
  const int t = planner.nearest_point({10.0, 10.0});
  EXPECT_EQ(planner.plan_between(s, t, 0.0, options).status, PlanStatus::kCancelled);
  PlanOptions capped;
  capped.node_cap = 5;
  const RoadPlan r = planner.plan_between(s, t, 0.0, capped);
  EXPECT_EQ(r.status, PlanStatus::kTimeout);
  EXPECT_LE(r.expanded, 6u);
  PlanOptions zero;
  zero.time_budget = std::chrono::microseconds(0);
  EXPECT_EQ(planner.plan_between(s, t, 0.0, zero).status, PlanStatus::kTimeout);
}

}  // namespace
}  // namespace fleet::planning

namespace fleet::planning {
namespace {

TEST(RoadPlanner, NearestPointFromTheIndexIsTheNearestOfAll) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    const map::RoadGraph g = random_graph(rng, 200 + trial * 50, 400);
    const RoadPlanner planner(g);
    std::uniform_real_distribution<double> coord(-5.0, 25.0);  // inside the points' box and around it
    for (int q = 0; q < 200; ++q) {
      const geometry::Vec2 p{coord(rng), coord(rng)};
      for (const auto use : {RoadPlanner::PointUse::kAny, RoadPlanner::PointUse::kRoute}) {
        int best = -1;
        double best_d2 = std::numeric_limits<double>::infinity();
        for (const auto& point : g.points) {
          const double d2 = (point.x - p.x) * (point.x - p.x) + (point.y - p.y) * (point.y - p.y);
          if (use == RoadPlanner::PointUse::kRoute && !planner.in_main_component(point.id)) continue;
          if (d2 < best_d2) {
            best_d2 = d2;
            best = point.id;
          }
        }
        ASSERT_EQ(planner.nearest_point(p, use), best) << "trial " << trial << " at " << p.x << ", " << p.y;
      }
    }
  }
}

TEST(RoadDistances, OneSearchGivesEveryStartTheShortestWayToTheGoal) {
  std::mt19937 rng(5);
  const map::RoadGraph g = random_graph(rng, 300, 500);
  RoadDistances distances(g);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(g.points.size()) - 1);
  for (int q = 0; q < 30; ++q) {
    const int goal = pick(rng);
    const auto& field = distances.to_point(goal);
    for (int k = 0; k < 20; ++k) {
      const int start = pick(rng);
      const double best = dijkstra(g, start, goal);
      if (std::isinf(best)) {
        EXPECT_TRUE(std::isinf(field[static_cast<std::size_t>(start)]));
      } else {
        EXPECT_NEAR(field[static_cast<std::size_t>(start)], best, 1e-3 * (1.0 + best));
      }
    }
  }
}

}  // namespace
}  // namespace fleet::planning
