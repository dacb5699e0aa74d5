#include "planning/plan_eval.hpp"

#include <gtest/gtest.h>

#include "map/site_map.hpp"
#include "planning/grid_astar.hpp"
#include "planning/ompl_planner.hpp"
#include "planning/road_planner.hpp"
#include "planning/route_planner.hpp"
#include "planning/static_grid.hpp"
#include "test_paths.hpp"

namespace fleet::planning {
namespace {

map::SiteMap load(const std::string& name) {
  return map::load_site_map_unchecked(map::site_path(fleet::test::source_dir() + "/maps", name));
}

TEST(PlanEval, TableARoadAStarAlwaysSucceeds) {
  const map::SiteMap s = load("table_a");
  PlanEvalConfiguration c;
  c.queries = 60;
  c.seed = 3;
  c.include_ompl = false;
  const PlanEvalReport r = run_plan_eval(s.site, s.graph.graph, c);
  ASSERT_EQ(r.planners.size(), 3u);
  const PlannerStats* road = r.find("road_astar");
  const PlannerStats* grid = r.find("grid_astar");
  const PlannerStats* grassfire = r.find("grassfire");
  ASSERT_NE(road, nullptr);
  ASSERT_NE(grid, nullptr);
  ASSERT_NE(grassfire, nullptr);
  EXPECT_EQ(grassfire->success, 1.0);
  EXPECT_EQ(road->success, 1.0);
  EXPECT_EQ(grid->success, 1.0);
  // Grid paths may cut corners inside the road squares, so they are never longer than the
  // centre-line route by much, and road A* is never shorter than the shortest found.
  EXPECT_GE(road->length_ratio, 1.0);
  EXPECT_GE(grid->length_ratio, 1.0);
  EXPECT_LE(grid->length_ratio, 1.05);
  EXPECT_LE(road->median_ms, road->p95_ms);
}

TEST(PlanEval, SameSeedSameQueriesSameLengths) {
  const map::SiteMap s = load("table_a");
  PlanEvalConfiguration c;
  c.queries = 20;
  c.include_ompl = false;
  const PlanEvalReport a = run_plan_eval(s.site, s.graph.graph, c);
  const PlanEvalReport b = run_plan_eval(s.site, s.graph.graph, c);
  EXPECT_DOUBLE_EQ(a.find("road_astar")->length_ratio, b.find("road_astar")->length_ratio);
  EXPECT_DOUBLE_EQ(a.find("grid_astar")->length_ratio, b.find("grid_astar")->length_ratio);
}

TEST(PlanEval, WarehouseGridAStarSucceedsAtLeastAsOftenAsOmpl) {
  const map::SiteMap s = load("warehouse");
  PlanEvalConfiguration c;
  c.queries = 25;
  c.optimal_budget_ms = 30.0;
  const PlanEvalReport r = run_plan_eval(s.site, s.graph.graph, c);
  EXPECT_EQ(r.grid_width, 800);
  EXPECT_EQ(r.grid_height, 400);
  const PlannerStats* grid = r.find("grid_astar");
  ASSERT_NE(grid, nullptr);
  EXPECT_EQ(grid->success, 1.0);
  EXPECT_LE(grid->length_ratio, 1.05);
  for (const auto& p : r.planners) {
    if (p.name.rfind("ompl_", 0) == 0) {
      EXPECT_GE(grid->success, p.success) << p.name;
    }
  }
  EXPECT_NE(r.find("ompl_rrtconnect"), nullptr);
  EXPECT_NE(r.find("ompl_bitstar"), nullptr);
}

// [Forklift thesis, Fig. 5.11] on the real table: switching on obstacle O2 in the middle of the table
// either re-routes or stops short of it, never through it.
TEST(PlanEval, TableAObstaclesNeverCrossed) {
  map::SiteMap s = load("table_a");
  StaticGrid grid({.resolution = 0.02, .obstacle_inflation = 0.1}, s.site, s.graph.graph);
  RoadPlanner road(s.graph.graph);
  for (const auto& o : s.site.static_obstacles) ASSERT_TRUE(grid.set_obstacle_enabled(o.id, true));
  road.set_obstacles(grid.grid());
  for (const auto& a : s.site.homes) {
    for (const auto& b : s.site.loading_areas) {
      const RoadPlan p = road.plan(a.pose, b.pose);
      ASSERT_TRUE(p.status == PlanStatus::kFound || p.status == PlanStatus::kBlockedPartial) << a.id << "->" << b.id;
      for (std::size_t k = 1; k < p.point_ids.size(); ++k) EXPECT_FALSE(road.blocked(p.point_ids[k]));
    }
  }
}

}  // namespace
}  // namespace fleet::planning

namespace fleet::planning {
namespace {

// From a home on the road to a loading area beside it and back: the grid legs leave and rejoin
// the road through the free corridor of the static grid.
TEST(RoutePlanner, TableAHomeToLoadingAreaAndBack) {
  const map::SiteMap s = load("table_a");
  StaticGrid sg({.resolution = 0.02}, s.site, s.graph.graph);
  auto grid = std::make_shared<const OccupancyGrid>(sg.grid());
  RoadPlanner road(s.graph.graph);
  road.set_obstacles(*grid);
  GridAStar astar;
  astar.set_grid(grid);
  RoutePlanner routes(road, astar);
  for (const auto& area : s.site.loading_areas) {
    const geometry::Pose2 home = s.site.homes.front().pose;
    for (const auto& [from, to] : {std::pair{home, area.pose}, std::pair{area.pose, home}}) {
      const Route r = routes.plan(from, to);
      ASSERT_EQ(r.status, PlanStatus::kFound) << area.id;
      EXPECT_NEAR(geometry::distance(r.points.front(), from.position()), 0.0, 1e-9);
      EXPECT_NEAR(geometry::distance(r.points.back(), to.position()), 0.0, 1e-9) << area.id;
      const GridPath& leg = to == area.pose ? r.from_road : r.to_road;
      ASSERT_EQ(leg.status, PlanStatus::kFound) << area.id;  // the area is off the graph
      for (std::size_t i = 1; i < leg.points.size(); ++i) {
        EXPECT_TRUE(grid->segment_free(leg.points[i - 1], leg.points[i])) << area.id;
      }
      EXPECT_GE(r.length, geometry::distance(from.position(), to.position()) - 1e-9);
    }
  }
}

}  // namespace
}  // namespace fleet::planning
