// The picker's global planner [Picker thesis, Algorithms 1 and 2]: the transform's values, paths
// that are free and near A*'s length, the planner interface's limits, and the cached transform.
#include "planning/grassfire_planner.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "planning/grid_astar.hpp"

namespace fleet::planning {
namespace {

using geometry::Vec2;

// One letter each, so the expected transforms below read as the grids they are.
constexpr std::int32_t X = GrassfirePlanner::kObstacle;
constexpr std::int32_t U = GrassfirePlanner::kUnreached;

// Row-major rows, top row first as printed: 1 marks an obstacle.
std::shared_ptr<OccupancyGrid> grid_from_rows(const std::vector<std::string>& rows) {
  const int h = static_cast<int>(rows.size());
  const int w = static_cast<int>(rows.front().size());
  auto g = std::make_shared<OccupancyGrid>(geometry::Bounds{0.0, 0.0, w * 1.0, h * 1.0}, 1.0);
  for (int r = 0; r < h; ++r) {
    for (int x = 0; x < w; ++x)
      g->set(x, h - 1 - r, rows[static_cast<std::size_t>(r)][static_cast<std::size_t>(x)] == '1');
  }
  return g;
}

std::shared_ptr<OccupancyGrid> random_grid(std::mt19937& rng, int w, int h, double density) {
  auto g = std::make_shared<OccupancyGrid>(geometry::Bounds{0.0, 0.0, w * 0.1, h * 0.1}, 0.1);
  std::bernoulli_distribution block(density);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) g->set(x, y, block(rng));
  return g;
}

Vec2 random_free(std::mt19937& rng, const OccupancyGrid& g) {
  std::uniform_int_distribution<int> px(0, g.width() - 1), py(0, g.height() - 1);
  while (true) {
    const int x = px(rng);
    const int y = py(rng);
    if (!g.occupied(x, y)) return g.cell_center(x, y);
  }
}

// Starts and ends exactly at the query's points, and no segment touches an occupied cell.
void expect_valid(const OccupancyGrid& g, const GridPath& p, Vec2 s, Vec2 t) {
  ASSERT_GE(p.points.size(), 1u);
  EXPECT_NEAR(geometry::distance(p.points.front(), s), 0.0, 1e-9);
  EXPECT_NEAR(geometry::distance(p.points.back(), t), 0.0, 1e-9);
  for (std::size_t i = 1; i < p.points.size(); ++i) {
    EXPECT_TRUE(g.segment_free(p.points[i - 1], p.points[i])) << "segment " << i << " crosses an obstacle";
  }
  EXPECT_NEAR(p.length, path_length(p.points), 1e-9);
}

// A comb of walls with gaps at alternating ends: the only route snakes through every bay.
std::shared_ptr<OccupancyGrid> comb(int teeth, double res, int gap = 8) {
  auto g = std::make_shared<OccupancyGrid>(geometry::Bounds{0.0, 0.0, 20.0, 10.0}, res);
  for (int k = 1; k <= teeth; ++k) {
    const int x = static_cast<int>(k * g->width() / (teeth + 1.0));
    for (int y = 0; y < g->height(); ++y) {
      const bool open = (k % 2 == 1) ? y >= g->height() - gap : y < gap;
      if (!open) g->set(x, y, true);
    }
  }
  return g;
}

// Hand-computed 4-neighbour distances around a wall: the wave flows around its end, and pockets
// sealed off by obstacles keep -1 [Picker thesis, section 4.3.1.2].
TEST(GrassfirePlanner, TransformMatchesHandComputedValues) {
  auto g = grid_from_rows({
      "00000",
      "01110",
      "00010",
      "11011",
      "00101",
  });
  GrassfirePlanner planner;
  planner.set_grid(g);
  // Goal: column 0 of the middle row (printed row 2, y = 2).
  const std::vector<std::int32_t> d = planner.complete_transform(g->cell_center(0, 2));
  // Grid rows bottom (y = 0) first, as the grid stores them.
  const std::vector<std::int32_t> expected = {
      U, U, X, U, X,  // y = 0: both bottom pockets are sealed off
      X, X, 3, X, X,  // y = 1
      0, 1, 2, X, 8,  // y = 2
      1, X, X, X, 7,  // y = 3
      2, 3, 4, 5, 6,  // y = 4
  };
  ASSERT_EQ(d.size(), expected.size());
  for (std::size_t i = 0; i < d.size(); ++i) EXPECT_EQ(d[i], expected[i]) << "cell " << i % 5 << ", " << i / 5;
}

TEST(GrassfirePlanner, DescendsWithWaypointsOnlyAtTurns) {
  // An open 10 x 6 floor: three diagonal steps, then two straight ones, one turn.
  auto g = std::make_shared<OccupancyGrid>(geometry::Bounds{0.0, 0.0, 10.0, 6.0}, 1.0);
  GrassfirePlanner planner;
  planner.set_grid(g);
  const Vec2 s = g->cell_center(1, 1);
  const Vec2 t = g->cell_center(6, 4);
  const GridPath p = planner.plan(s, t, {});
  ASSERT_EQ(p.status, PlanStatus::kFound);
  ASSERT_EQ(p.points.size(), 3u);
  EXPECT_NEAR(geometry::distance(p.points[1], g->cell_center(4, 4)), 0.0, 1e-9);
  EXPECT_NEAR(p.length, 3.0 * std::sqrt(2.0) + 2.0, 1e-9);
}

TEST(GrassfirePlanner, NeverCutsACornerBetweenDiagonalObstacles) {
  // Start and goal touch at a corner pinched between two obstacles: the descent's cheapest step
  // (straight onto the goal, value 0) would squeeze through, so it walks around instead.
  auto g = grid_from_rows({
      "0000",
      "0100",
      "1000",
  });
  GrassfirePlanner planner;
  planner.set_grid(g);
  const Vec2 s = g->cell_center(1, 0);
  const Vec2 t = g->cell_center(0, 1);
  const GridPath p = planner.plan(s, t, {});
  ASSERT_EQ(p.status, PlanStatus::kFound);
  expect_valid(*g, p, s, t);
  EXPECT_NEAR(p.length, 6.0, 1e-9);
}

TEST(GrassfirePlanner, RandomGridsFreePathsWithinAFactorOfAStar) {
  std::mt19937 rng(17);
  GrassfirePlanner grassfire;
  GridAStar astar({.jump_points = true, .smooth = false});
  int found = 0;
  double ratio_sum = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const double density = trial < 3 ? 0.0 : 0.05 + 0.01 * trial;
    auto g = random_grid(rng, 60, 40, density);
    grassfire.set_grid(g);
    astar.set_grid(g);
    for (int q = 0; q < 15; ++q) {
      const Vec2 s = random_free(rng, *g);
      const Vec2 t = random_free(rng, *g);
      const GridPath a = astar.plan(s, t, {});
      const GridPath b = grassfire.plan(s, t, {});
      // Both are complete on the same 8-connected, no-corner-cutting moves.
      ASSERT_EQ(b.status, a.status) << "trial " << trial << " query " << q;
      if (a.status != PlanStatus::kFound) continue;
      ++found;
      expect_valid(*g, b, s, t);
      // The descent's length is at most its 4-neighbour distance, which is at most sqrt(2) times
      // the shortest 8-connected path; on an empty floor it is that path.
      ASSERT_LE(b.length, std::sqrt(2.0) * a.length + 1e-9) << "trial " << trial << " query " << q;
      if (density == 0.0) {
        EXPECT_NEAR(b.length, a.length, 1e-9) << "trial " << trial << " query " << q;
      }
      ratio_sum += a.length > 0.0 ? b.length / a.length : 1.0;
    }
  }
  EXPECT_GT(found, 200);
  EXPECT_LT(ratio_sum / found, 1.05);
  RecordProperty("mean_length_ratio_to_astar", std::to_string(ratio_sum / found));
}

TEST(GrassfirePlanner, UnreachableGoalIsNoPathAndStaysSo) {
  auto g = comb(6, 0.05);
  for (int y = 0; y < g->height(); ++y) g->set(g->width() - 3, y, true);
  GrassfirePlanner planner;
  planner.set_grid(g);
  const GridPath first = planner.plan({0.5, 0.5}, {19.95, 0.5}, {});
  EXPECT_EQ(first.status, PlanStatus::kNoPath);
  EXPECT_GT(first.expanded, 0u);
  // The burnt-out transform is cached: the next start to the same goal knows at once.
  const GridPath again = planner.plan({5.0, 9.5}, {19.95, 0.5}, {});
  EXPECT_EQ(again.status, PlanStatus::kNoPath);
  EXPECT_EQ(again.expanded, 0u);
}

TEST(GrassfirePlanner, InvalidStartOrGoal) {
  auto g = comb(6, 0.05);
  g->set(0, 0, true);
  GrassfirePlanner planner;
  EXPECT_EQ(planner.plan({0.5, 0.5}, {1.0, 1.0}, {}).status, PlanStatus::kInvalidStart);  // no grid yet
  EXPECT_TRUE(planner.complete_transform({1.0, 1.0}).empty());
  planner.set_grid(g);
  EXPECT_EQ(planner.plan({0.01, 0.01}, {19.5, 0.5}, {}).status, PlanStatus::kInvalidStart);
  EXPECT_EQ(planner.plan({19.5, 0.5}, {0.01, 0.01}, {}).status, PlanStatus::kInvalidStart);
  EXPECT_EQ(planner.plan({0.5, 0.5}, {25.0, 0.5}, {}).status, PlanStatus::kInvalidStart);
  EXPECT_EQ(planner.plan({-1.0, 0.5}, {0.5, 0.5}, {}).status, PlanStatus::kInvalidStart);
  EXPECT_TRUE(planner.complete_transform({0.01, 0.01}).empty());
}

TEST(GrassfirePlanner, NodeCapStopsAndTheNextQueryResumes) {
  auto g = comb(6, 0.05);
  const Vec2 s{0.5, 0.5};
  const Vec2 t{19.5, 0.5};
  GrassfirePlanner fresh;
  fresh.set_grid(g);
  const GridPath whole = fresh.plan(s, t, {});
  ASSERT_EQ(whole.status, PlanStatus::kFound);

  GrassfirePlanner capped;
  capped.set_grid(g);
  PlanOptions o;
  o.node_cap = 3;
  const GridPath stopped = capped.plan(s, t, o);
  EXPECT_EQ(stopped.status, PlanStatus::kTimeout);
  EXPECT_LE(stopped.expanded, 3u);
  // Each capped query burns on from where the last one stopped, so the same path comes out.
  o.node_cap = whole.expanded / 4 + 1;
  GridPath resumed;
  int queries = 0;
  do {
    resumed = capped.plan(s, t, o);
    EXPECT_LE(resumed.expanded, o.node_cap);
    ++queries;
  } while (resumed.status == PlanStatus::kTimeout && queries < 10);
  ASSERT_EQ(resumed.status, PlanStatus::kFound);
  EXPECT_GE(queries, 4);
  EXPECT_EQ(resumed.points, whole.points);
}

TEST(GrassfirePlanner, StopsOnTheCancelFlagAndTheTimeBudget) {
  // 1000 x 500 cells at 2 cm, the goal in the last bay: the wave has the whole comb to burn.
  auto g = comb(40, 0.02);
  const Vec2 s{0.1, 0.1};
  const Vec2 t{19.99, 0.1};
  GrassfirePlanner planner;
  planner.set_grid(g);
  std::atomic<bool> cancel{true};
  PlanOptions o;
  o.cancel = &cancel;
  EXPECT_EQ(planner.plan(s, t, o).status, PlanStatus::kCancelled);
  // A raised flag also stops a query the cache could answer.
  cancel.store(false);
  ASSERT_EQ(planner.plan(s, t, o).status, PlanStatus::kFound);
  cancel.store(true);
  EXPECT_EQ(planner.plan(s, t, o).status, PlanStatus::kCancelled);

  GrassfirePlanner slow;
  slow.set_grid(g);
  PlanOptions none;
  none.time_budget = std::chrono::microseconds(0);
  const GridPath late = slow.plan(s, t, none);
  EXPECT_EQ(late.status, PlanStatus::kTimeout);
  EXPECT_EQ(late.expanded, 0u);
}

TEST(GrassfirePlanner, CachedTransformGivesTheSamePath) {
  std::mt19937 rng(23);
  auto g = random_grid(rng, 80, 50, 0.2);
  const Vec2 t = random_free(rng, *g);
  GrassfirePlanner cached;
  cached.set_grid(g);
  cached.complete_transform(t);
  int found = 0;
  for (int q = 0; q < 40; ++q) {
    const Vec2 s = random_free(rng, *g);
    GrassfirePlanner cold;
    cold.set_grid(g);
    const GridPath a = cold.plan(s, t, {});
    const GridPath b = cached.plan(s, t, {});
    ASSERT_EQ(a.status, b.status) << "query " << q;
    // The whole transform is there: no query to this goal expands a cell.
    EXPECT_EQ(b.expanded, 0u);
    if (a.status != PlanStatus::kFound) continue;
    ++found;
    EXPECT_EQ(a.points, b.points) << "query " << q;
  }
  EXPECT_GT(found, 10);
  // A new goal replaces the cached transform; going back to the first rebuilds the same one.
  const Vec2 other = random_free(rng, *g);
  const Vec2 from_other = random_free(rng, *g);
  GrassfirePlanner cold;
  cold.set_grid(g);
  const GridPath to_other = cached.plan(from_other, other, {});
  EXPECT_EQ(to_other.status, cold.plan(from_other, other, {}).status);
  EXPECT_EQ(to_other.points, cold.plan(from_other, other, {}).points);
  EXPECT_EQ(cached.complete_transform(other), cold.complete_transform(other));
  GrassfirePlanner reference;
  reference.set_grid(g);
  EXPECT_EQ(cached.complete_transform(t), reference.complete_transform(t));
}

}  // namespace
}  // namespace fleet::planning
