#include <gtest/gtest.h>

#include <random>

#include "planning/dynamic_grid.hpp"
#include "planning/lidar_sim.hpp"
#include "planning/local_planner.hpp"
#include "planning/octomap_layer.hpp"
#include "test_graphs.hpp"

namespace fleet::planning {
namespace {

using geometry::Vec2;
using testing::square;

OctoMapConfiguration octo_config(geometry::Bounds area, double leaf, double cell) {
  OctoMapConfiguration c;
  c.resolution = leaf;
  c.area = area;
  c.projection_resolution = cell;
  return c;
}

// ---- OctoMap layer ----------------------------------------------------------------------------

class OctoMapRoundTrip : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(OctoMapRoundTrip, GridToTreeToGrid) {
  const auto [leaf, cell] = GetParam();
  const geometry::Bounds area{0.0, 0.0, 2.0, 1.6};
  OccupancyGrid grid(area, cell);
  std::mt19937 rng(4);
  std::bernoulli_distribution block(0.3);
  for (int y = 0; y < grid.height(); ++y)
    for (int x = 0; x < grid.width(); ++x) grid.set(x, y, block(rng));
  OctoMapLayer layer(octo_config(area, leaf, cell));
  layer.insert_grid(grid);
  OccupancyGrid back(area, cell);
  layer.project(back);
  EXPECT_EQ(back.cells(), grid.cells());
  // The incrementally kept projection agrees with the one read from the tree.
  EXPECT_EQ(layer.sensed().cells(), grid.cells());
  // Free cells read back as known free leaves, occupied ones as occupied.
  EXPECT_EQ(layer.leaf_state(grid.cell_center(3, 4)), grid.occupied(3, 4) ? 1 : 0);
  EXPECT_EQ(layer.leaf_state({5.0, 5.0}), -1);
}

INSTANTIATE_TEST_SUITE_P(Resolutions, OctoMapRoundTrip,
                         ::testing::Values(std::make_pair(0.02, 0.02), std::make_pair(0.02, 0.04),
                                           std::make_pair(0.02, 0.05), std::make_pair(0.05, 0.1)));

TEST(OctoMapLayer, ScansMarkHitsAndClearFreeSpace) {
  const geometry::Bounds area{0.0, 0.0, 4.0, 4.0};
  OctoMapLayer layer(octo_config(area, 0.02, 0.05));
  LidarSim lidar;
  const std::vector<geometry::Polygon> obstacles{square(3.0, 2.0, 0.3)};
  const LidarScan scan = lidar.scan({2.0, 2.0, 0.0}, obstacles);
  // The beam straight ahead (+x) hits the box's near face at x = 2.85.
  const std::size_t ahead = scan.ranges.size() / 2;
  ASSERT_NEAR(scan.ranges[ahead], 0.85, 1e-9);
  EXPECT_FALSE(std::isfinite(scan.ranges[0]));  // nothing behind within 4 m... inside the area edge
  for (int i = 0; i < 5; ++i) layer.insert_scan(scan);
  EXPECT_EQ(layer.leaf_state({2.85, 2.0}), 1);
  EXPECT_EQ(layer.leaf_state({2.5, 2.0}), 0);
  EXPECT_EQ(layer.leaf_state({3.2, 2.0}), -1);  // behind the face: never seen
  EXPECT_TRUE(layer.sensed().occupied_at({2.85, 2.0}));
  EXPECT_FALSE(layer.sensed().occupied_at({2.5, 2.0}));
  OccupancyGrid projected(area, 0.05);
  layer.project(projected);
  EXPECT_EQ(projected.cells(), layer.sensed().cells());

  // The obstacle leaves: repeated scans clear it again (log-odds fall back through the threshold).
  int scans = 0;
  const LidarScan empty = lidar.scan({2.0, 2.0, 0.0}, {});
  while (layer.leaf_state({2.85, 2.0}) == 1 && scans < 50) {
    layer.insert_scan(empty);
    ++scans;
  }
  EXPECT_EQ(layer.leaf_state({2.85, 2.0}), 0);
  EXPECT_GT(scans, 1);  // clamping keeps some evidence: one miss does not undo five hits
  EXPECT_FALSE(layer.sensed().occupied_at({2.85, 2.0}));
  OccupancyGrid again(area, 0.05);
  layer.project(again);
  EXPECT_EQ(again.cells(), layer.sensed().cells());
}

TEST(OctoMapLayer, AssumedFreeItHoldsEveryLeafFromTheStartAndStillSeesWhatComes) {
  const geometry::Bounds area{0.0, 0.0, 12.0, 4.0};
  OctoMapLayer layer(octo_config(area, 0.05, 0.05));
  layer.assume_free();
  const std::size_t leaves = layer.leaf_count();
  EXPECT_GE(leaves, static_cast<std::size_t>(240 * 80));
  EXPECT_EQ(layer.leaf_state({11.0, 3.0}), 0);
  EXPECT_FALSE(layer.sensed().occupied_at({11.0, 3.0}));
  // Scans from all over the area add no leaf: its memory does not grow with the ground covered.
  LidarSim lidar;
  const std::vector<geometry::Polygon> obstacles{square(3.0, 2.0, 0.3), square(11.0, 2.0, 0.3)};
  for (double x = 1.0; x < 12.0; x += 1.0) {
    for (int i = 0; i < 3; ++i) layer.insert_scan(lidar.scan({x, 2.0, 0.0}, obstacles));
  }
  EXPECT_EQ(layer.leaf_count(), leaves);
  EXPECT_EQ(layer.leaf_state({2.85, 2.0}), 1);
  EXPECT_TRUE(layer.sensed().occupied_at({2.85, 2.0}));
  EXPECT_FALSE(layer.sensed().occupied_at({2.5, 2.0}));
  OccupancyGrid projected(area, 0.05);
  layer.project(projected);
  EXPECT_EQ(projected.cells(), layer.sensed().cells());
}

TEST(LidarSim, RangesToPolygonFaces) {
  LidarSim lidar({.beams = 4, .max_range = 4.0});
  const std::vector<geometry::Polygon> obstacles{square(0.0, 1.0, 0.2), square(10.0, 0.0, 1.0)};
  const LidarScan s = lidar.scan({0.0, 0.0, 0.0}, obstacles);
  // Beams at -pi, -pi/2, 0, pi/2 from the sensor's heading.
  EXPECT_NEAR(s.ranges[3], 0.9, 1e-9);
  EXPECT_FALSE(std::isfinite(s.ranges[2]));  // the far box is beyond max range
  EXPECT_FALSE(std::isfinite(s.ranges[0]));
}

// ---- dynamic grid -----------------------------------------------------------------------------

TEST(DynamicGrid, FreshNeighbourGrowsWithSpeedTimesAge) {
  OccupancyGrid base({0.0, 0.0, 4.0, 4.0}, 0.02);
  DynamicGrid dyn({.own_radius = 0.0, .safety_margin = 0.0});
  Neighbour n;
  n.pose = {2.0, 2.0, 0.0};
  n.footprint = {0.25, 0.16};
  n.speed = 0.4;
  n.age = 0.0;
  dyn.update(base, std::span<const Neighbour>(&n, 1), nullptr);
  EXPECT_TRUE(dyn.grid().occupied_at({2.1, 2.0}));
  EXPECT_FALSE(dyn.grid().occupied_at({2.2, 2.0}));
  n.age = 0.25;  // may have moved 0.1 m since
  dyn.update(base, std::span<const Neighbour>(&n, 1), nullptr);
  EXPECT_TRUE(dyn.grid().occupied_at({2.2, 2.0}));
  EXPECT_FALSE(dyn.grid().occupied_at({2.3, 2.0}));
}

TEST(DynamicGrid, AStaleNeighbourGrowsAtTopSpeedOnlyForTheTimeBeyondStaleAfter) {
  OccupancyGrid base({0.0, 0.0, 4.0, 4.0}, 0.02);
  DynamicGrid dyn({.own_radius = 0.0, .safety_margin = 0.0, .stale_after = 0.5, .max_speed = 0.5});
  Neighbour n;
  n.pose = {2.0, 2.0, 0.0};
  n.footprint = {0.25, 0.16};
  n.speed = 0.0;  // it reported standing still
  n.age = 0.49;
  dyn.update(base, std::span<const Neighbour>(&n, 1), nullptr);
  EXPECT_FALSE(dyn.is_stale(n));
  EXPECT_FALSE(dyn.grid().occupied_at({2.0, 2.12}));
  // A little late: it may have started off for 0.1 s, 5 cm at most, not 0.55 s at top speed.
  n.age = 0.6;
  EXPECT_TRUE(dyn.is_stale(n));
  EXPECT_NEAR(distance_since_seen(n.speed, n.age, 0.5, 0.5), 0.05, 1e-12);
  dyn.update(base, std::span<const Neighbour>(&n, 1), nullptr);
  EXPECT_TRUE(dyn.grid().occupied_at({2.0, 2.12}));
  EXPECT_FALSE(dyn.grid().occupied_at({2.0, 2.16}));
  // Long stale: 0.5 m/s x 1.5 s beyond, in every direction, sideways and behind too.
  n.age = 2.0;
  dyn.update(base, std::span<const Neighbour>(&n, 1), nullptr);
  for (double a = 0.0; a < 6.28; a += 0.5) {
    EXPECT_TRUE(dyn.grid().occupied_at({2.0 + 0.8 * std::cos(a), 2.0 + 0.8 * std::sin(a)})) << a;
  }
  EXPECT_FALSE(dyn.grid().occupied_at({2.0, 2.9}));
  // The growth has no jump at stale_after, and a moving one keeps its reported speed until then.
  EXPECT_NEAR(distance_since_seen(0.4, 0.5, 0.5, 0.5), 0.2, 1e-12);
  EXPECT_NEAR(distance_since_seen(0.4, 0.5 + 1e-9, 0.5, 0.5), 0.2, 1e-8);
  EXPECT_NEAR(distance_since_seen(0.4, 0.7, 0.5, 0.5), 0.3, 1e-12);
  // A cap keeps a long-silent robot from closing the whole map.
  DynamicGrid capped({.own_radius = 0.0, .safety_margin = 0.0, .stale_after = 0.5, .max_speed = 0.5, .max_reach = 0.3});
  n.age = 100.0;
  capped.update(base, std::span<const Neighbour>(&n, 1), nullptr);
  EXPECT_TRUE(capped.grid().occupied_at({2.0, 2.35}));
  EXPECT_FALSE(capped.grid().occupied_at({2.0, 2.42}));
}

TEST(DynamicGrid, OwnRadiusGrowsEverythingAndStaticStays) {
  OccupancyGrid base({0.0, 0.0, 2.0, 2.0}, 0.02);
  base.set(10, 10, true);
  OccupancyGrid sensed({0.0, 0.0, 2.0, 2.0}, 0.02);
  sensed.set(50, 50, true);
  DynamicGrid dyn({.own_radius = 0.1});
  dyn.update(base, {}, &sensed);
  EXPECT_TRUE(dyn.grid().occupied(10, 10));
  EXPECT_FALSE(dyn.dynamic_layer().occupied(10, 10));
  EXPECT_TRUE(dyn.grid().occupied(55, 50));
  EXPECT_FALSE(dyn.grid().occupied(56, 50));
  OccupancyGrid other({0.0, 0.0, 2.0, 2.0}, 0.05);
  EXPECT_THROW(dyn.update(base, {}, &other), std::invalid_argument);
}

// ---- local planning ---------------------------------------------------------------------------

struct LocalWorld {
  map::RoadGraph graph;
  map::Site site;
  StaticGrid static_grid;
  RoadPlanner road;
  DynamicGrid dynamic;
  LocalPlanner local;

  explicit LocalWorld(map::RoadGraph g)
      : graph(std::move(g)),
        site(testing::site_for(graph)),
        static_grid({.resolution = 0.02}, site, graph),
        road(graph),
        dynamic({.own_radius = 0.1, .safety_margin = 0.02}),
        local({.min_lookahead = 1.0, .clear_cycles = 2}, static_grid, road) {}

  LocalStep cycle(const geometry::Pose2& pose, std::vector<Neighbour> others) {
    dynamic.update(static_grid.permanent_grid(), others, nullptr);
    return local.step(pose, 0.2, dynamic);
  }
};

Neighbour robot_at(double x, double y) {
  Neighbour n;
  n.id = "r2";
  n.pose = {x, y, 0.0};
  n.footprint = {0.25, 0.16};
  return n;
}

TEST(LocalPlanner, TemporaryObstacleForRobotInTheWayGoesAfterItLeaves) {
  // A ring of roads: the short way from (0.3,0.3) to (2.3,0.3) runs along y = 0.3.
  LocalWorld w(testing::lattice_graph(3, 2, 1.0, 0.1));
  const geometry::Pose2 me{0.3, 0.3, 0.0};
  w.local.set_goal({2.3, 0.3, 0.0});
  LocalStep s = w.cycle(me, {});
  EXPECT_TRUE(s.replanned);
  ASSERT_EQ(s.status, PlanStatus::kFound);
  EXPECT_NEAR(w.local.plan().length, 2.0, 1e-9);
  EXPECT_FALSE(s.collision_ahead);
  EXPECT_NEAR(s.free_distance, 1.0, 1e-9);

  // Another robot stands on the road 0.7 m ahead.
  s = w.cycle(me, {robot_at(1.0, 0.3)});
  ASSERT_EQ(s.added.size(), 1u);
  EXPECT_TRUE(s.replanned);
  EXPECT_EQ(w.static_grid.temporaries().size(), 1u);
  EXPECT_EQ(s.status, PlanStatus::kFound);  // the detour round the ring
  EXPECT_NEAR(w.local.plan().length, 4.0, 1e-9);
  EXPECT_FALSE(s.collision_ahead);
  for (const auto& p : w.local.plan().points) EXPECT_FALSE(w.dynamic.dynamic_layer().occupied_at(p));

  // While it stays, nothing changes.
  s = w.cycle(me, {robot_at(1.0, 0.3)});
  EXPECT_TRUE(s.added.empty());
  EXPECT_TRUE(s.removed.empty());
  EXPECT_FALSE(s.replanned);

  // It leaves; after clear_cycles cycles seen free the temporary goes and the short way is back.
  s = w.cycle(me, {robot_at(1.0, 1.8)});
  EXPECT_TRUE(s.removed.empty());
  s = w.cycle(me, {robot_at(1.0, 1.8)});
  ASSERT_EQ(s.removed.size(), 1u);
  EXPECT_EQ(s.removed[0], s.removed[0]);
  EXPECT_TRUE(w.static_grid.temporaries().empty());
  EXPECT_TRUE(s.replanned);
  EXPECT_NEAR(w.local.plan().length, 2.0, 1e-9);
}

TEST(LocalPlanner, RobotOnTheOnlyRoadMakesUsWaitBeforeIt) {
  LocalWorld w(testing::lattice_graph(3, 1, 1.0, 0.1));  // one straight road
  const geometry::Pose2 me{0.3, 0.3, 0.0};
  w.local.set_goal({2.3, 0.3, 0.0});
  w.cycle(me, {});
  const LocalStep s = w.cycle(me, {robot_at(1.2, 0.3)});
  ASSERT_EQ(s.added.size(), 1u);
  EXPECT_EQ(s.status, PlanStatus::kBlockedPartial);
  ASSERT_FALSE(w.local.plan().points.empty());
  const Vec2 end = w.local.plan().points.back();
  EXPECT_LT(end.x, 1.2 - 0.125 - 0.1);  // stops short of the robot's body grown by our radius
  EXPECT_FALSE(s.collision_ahead);
}

TEST(LocalPlanner, StaleNeighbourSlowsUsDown) {
  LocalWorld w(testing::lattice_graph(3, 1, 1.0, 0.1));
  const geometry::Pose2 me{0.3, 0.3, 0.0};
  w.local.set_goal({2.3, 0.3, 0.0});
  w.cycle(me, {});
  Neighbour n = robot_at(2.0, 0.3);
  n.age = 0.2;
  LocalStep s = w.cycle(me, {n});
  EXPECT_TRUE(s.added.empty());  // 1.7 m away: outside the 1 m lookahead
  n.age = 2.0;                   // silent for 2 s: it could be 1 m closer by now
  s = w.cycle(me, {n});
  EXPECT_FALSE(s.added.empty());
  EXPECT_EQ(s.status, PlanStatus::kBlockedPartial);
}

// The same story seen by the lidar alone (no FleetView): the robot's true footprint enters the
// OctoMap through scans, the temporary obstacle follows, and it goes once scans see the road free.
TEST(LocalPlanner, LidarOnlyObstacleMakesAndClearsATemporary) {
  LocalWorld w(testing::lattice_graph(3, 2, 1.0, 0.1));
  OctoMapConfiguration oc;
  oc.resolution = 0.02;
  oc.area = w.site.bounds;
  oc.projection_resolution = 0.02;
  OctoMapLayer octo(oc);
  LidarSim lidar;
  const geometry::Pose2 me{0.3, 0.3, 0.0};
  w.local.set_goal({2.3, 0.3, 0.0});
  auto cycle = [&](const std::vector<geometry::Polygon>& truth) {
    octo.insert_scan(lidar.scan(me, truth));
    w.dynamic.update(w.static_grid.permanent_grid(), {}, &octo.sensed());
    return w.local.step(me, 0.2, w.dynamic);
  };
  const std::vector<geometry::Polygon> robot{geometry::footprint_polygon({1.0, 0.3, 0.0}, {0.25, 0.16})};
  LocalStep s = cycle({});
  ASSERT_EQ(s.status, PlanStatus::kFound);
  EXPECT_NEAR(w.local.plan().length, 2.0, 1e-9);
  int added = 0;
  for (int k = 0; k < 3; ++k) added += static_cast<int>(cycle(robot).added.size());
  EXPECT_EQ(added, 1);
  EXPECT_NEAR(w.local.plan().length, 4.0, 1e-9);  // round the ring
  int cycles = 0;
  while (!w.static_grid.temporaries().empty() && cycles < 30) {
    cycle({});
    ++cycles;
  }
  EXPECT_TRUE(w.static_grid.temporaries().empty());
  EXPECT_GE(cycles, 2);  // log-odds and clear_cycles both need evidence, not one scan
  EXPECT_NEAR(w.local.plan().length, 2.0, 1e-9);
}

}  // namespace
}  // namespace fleet::planning
