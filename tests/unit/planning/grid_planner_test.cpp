#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <random>
#include <thread>

#include "planning/grid_astar.hpp"

namespace fleet::planning {
namespace {

using geometry::Vec2;

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

void expect_valid(const OccupancyGrid& g, const GridPath& p, Vec2 s, Vec2 t) {
  ASSERT_GE(p.points.size(), 1u);
  EXPECT_NEAR(geometry::distance(p.points.front(), s), 0.0, 1e-9);
  EXPECT_NEAR(geometry::distance(p.points.back(), t), 0.0, 1e-9);
  for (std::size_t i = 1; i < p.points.size(); ++i) {
    EXPECT_TRUE(g.segment_free(p.points[i - 1], p.points[i])) << "segment " << i << " crosses an obstacle";
  }
}

// Jump point search must return the optimum of textbook A* (same movement rule) on every query.
TEST(GridAStar, JumpPointSearchMatchesPlainAStar) {
  std::mt19937 rng(11);
  GridAStar jps({.jump_points = true, .smooth = false});
  GridAStar plain({.jump_points = false, .smooth = false});
  int found = 0;
  std::size_t jps_expanded = 0;
  std::size_t plain_expanded = 0;
  for (int trial = 0; trial < 30; ++trial) {
    // Empty and sparse grids exercise long straight jumps and goals on a jump's line; denser
    // ones the forced neighbours.
    const double density = trial < 4 ? 0.0 : trial < 10 ? 0.02 : 0.1 + 0.01 * trial;
    auto g = random_grid(rng, 60, 40, density);
    jps.set_grid(g);
    plain.set_grid(g);
    for (int q = 0; q < 20; ++q) {
      const Vec2 s = random_free(rng, *g);
      const Vec2 t = random_free(rng, *g);
      const GridPath a = jps.plan(s, t, {});
      const GridPath b = plain.plan(s, t, {});
      ASSERT_EQ(a.status, b.status) << "trial " << trial << " query " << q;
      if (a.status != PlanStatus::kFound) continue;
      ++found;
      EXPECT_NEAR(a.length, b.length, 1e-6) << "trial " << trial << " query " << q;
      expect_valid(*g, a, s, t);
      jps_expanded += a.expanded;
      plain_expanded += b.expanded;
    }
  }
  EXPECT_GT(found, 200);
  EXPECT_LT(jps_expanded, plain_expanded);
}

TEST(GridAStar, SmoothingShortensAndStaysFree) {
  std::mt19937 rng(5);
  GridAStar raw({.jump_points = true, .smooth = false});
  GridAStar smooth({.jump_points = true, .smooth = true});
  for (int trial = 0; trial < 10; ++trial) {
    auto g = random_grid(rng, 80, 50, 0.15);
    raw.set_grid(g);
    smooth.set_grid(g);
    for (int q = 0; q < 20; ++q) {
      const Vec2 s = random_free(rng, *g);
      const Vec2 t = random_free(rng, *g);
      const GridPath a = raw.plan(s, t, {});
      const GridPath b = smooth.plan(s, t, {});
      ASSERT_EQ(a.status, b.status);
      if (a.status != PlanStatus::kFound) continue;
      EXPECT_LE(b.length, a.length + 1e-9);
      EXPECT_GE(b.length, geometry::distance(s, t) - 1e-9);
      expect_valid(*g, b, s, t);
    }
  }
}

TEST(GridAStar, WallWithoutGapIsNoPathAndOccupiedStartIsInvalid) {
  auto g = std::make_shared<OccupancyGrid>(geometry::Bounds{0.0, 0.0, 2.0, 1.0}, 0.1);
  for (int y = 0; y < g->height(); ++y) g->set(10, y, true);
  GridAStar planner;
  planner.set_grid(g);
  EXPECT_EQ(planner.plan({0.25, 0.5}, {1.75, 0.5}, {}).status, PlanStatus::kNoPath);
  EXPECT_EQ(planner.plan({1.05, 0.5}, {1.75, 0.5}, {}).status, PlanStatus::kInvalidStart);
  EXPECT_EQ(planner.plan({-1.0, 0.5}, {1.75, 0.5}, {}).status, PlanStatus::kInvalidStart);
  g->set(10, 3, false);  // a gap; the planner works on its own copy until set_grid again
  EXPECT_EQ(planner.plan({0.25, 0.5}, {1.75, 0.5}, {}).status, PlanStatus::kNoPath);
  planner.set_grid(g);
  const GridPath p = planner.plan({0.25, 0.5}, {1.75, 0.5}, {});
  ASSERT_EQ(p.status, PlanStatus::kFound);
  expect_valid(*g, p, {0.25, 0.5}, {1.75, 0.5});
}

TEST(GridAStar, NoCornerCutting) {
  auto g = std::make_shared<OccupancyGrid>(geometry::Bounds{0.0, 0.0, 0.3, 0.3}, 0.1);
  // Only a diagonal squeeze between (1,0)/(0,1) would connect (0,0) to (1,1); it is refused.
  g->set(1, 0, true);
  g->set(0, 1, true);
  GridAStar planner;
  planner.set_grid(g);
  EXPECT_EQ(planner.plan({0.05, 0.05}, {0.15, 0.15}, {}).status, PlanStatus::kNoPath);
}

}  // namespace
}  // namespace fleet::planning
