// Every planner honours its time budget, node cap and cancel flag (STYLE 6), and the OMPL
// planners find valid paths on the same grids as grid A*.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <thread>

#include "planning/grid_astar.hpp"
#include "planning/ompl_planner.hpp"
#include "planning/road_planner.hpp"
#include "test_graphs.hpp"

namespace fleet::planning {
namespace {

using geometry::Vec2;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
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

std::vector<std::unique_ptr<GridPlanner>> all_grid_planners() {
  std::vector<std::unique_ptr<GridPlanner>> v;
  v.push_back(std::make_unique<GridAStar>());
  v.push_back(std::make_unique<GridAStar>(GridAStarConfiguration{.jump_points = false}));
  v.push_back(std::make_unique<OmplGridPlanner>(OmplPlannerConfiguration{.algorithm = OmplAlgorithm::kRrtConnect}));
  v.push_back(std::make_unique<OmplGridPlanner>(OmplPlannerConfiguration{.algorithm = OmplAlgorithm::kRrtStar}));
  v.push_back(std::make_unique<OmplGridPlanner>(OmplPlannerConfiguration{.algorithm = OmplAlgorithm::kBitStar}));
  return v;
}

class PlannerLimits : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    quiet_ompl_logs();
    seed_ompl(42);
  }
};

TEST_F(PlannerLimits, EveryGridPlannerFindsAValidPathThroughTheComb) {
  auto g = comb(4, 0.05, 30);
  const Vec2 s{0.5, 0.5};
  const Vec2 t{19.5, 0.5};
  for (auto& p : all_grid_planners()) {
    p->set_grid(g);
    PlanOptions o;
    // The optimising planners spend all of it; RRTConnect and grid A* return at once.
    o.time_budget = std::chrono::milliseconds(1500);
    const GridPath path = p->plan(s, t, o);
    ASSERT_EQ(path.status, PlanStatus::kFound) << p->name();
    // The snake crosses the 10 m tall comb four times, each time at least 10 - 2 x 1.5 m.
    EXPECT_GT(path.length, 4 * 7.0) << p->name();
    // Dense sampling at a quarter cell: no sample inside an occupied cell.
    for (std::size_t i = 1; i < path.points.size(); ++i) {
      const Vec2 a = path.points[i - 1];
      const Vec2 b = path.points[i];
      const int n = static_cast<int>(std::ceil(geometry::distance(a, b) / (0.25 * g->resolution()))) + 1;
      for (int k = 0; k <= n; ++k) {
        ASSERT_FALSE(g->occupied_at(a + (static_cast<double>(k) / n) * (b - a))) << p->name() << " segment " << i;
      }
    }
  }
}

TEST_F(PlannerLimits, EveryGridPlannerHonoursItsTimeBudget) {
  // A 1000 x 500 comb at 2 cm with the goal walled off: no planner can finish early.
  auto g = comb(40, 0.02);
  for (int y = 0; y < g->height(); ++y) g->set(g->width() - 3, y, true);
  const Vec2 s{0.1, 0.1};
  const Vec2 t{19.99, 0.1};
  for (auto& p : all_grid_planners()) {
    p->set_grid(g);
    PlanOptions o;
    o.time_budget = std::chrono::milliseconds(20);
    const auto t0 = Clock::now();
    const GridPath path = p->plan(s, t, o);
    const double ms = ms_since(t0);
    // Grid A* may prove there is no path inside the budget; the sampling planners run out.
    EXPECT_TRUE(path.status == PlanStatus::kTimeout || path.status == PlanStatus::kNoPath) << p->name();
    // Generous slack for a loaded machine; what matters is that 20 ms do not become seconds.
    EXPECT_LT(ms, 20.0 + 80.0) << p->name();
  }
}

TEST_F(PlannerLimits, EveryGridPlannerStopsOnTheCancelFlag) {
  auto g = comb(40, 0.02);
  for (int y = 0; y < g->height(); ++y) g->set(g->width() - 3, y, true);
  for (auto& p : all_grid_planners()) {
    p->set_grid(g);
    std::atomic<bool> cancel{false};
    PlanOptions o;
    o.time_budget = std::chrono::seconds(30);
    o.cancel = &cancel;
    std::thread raiser([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      cancel.store(true);
    });
    const auto t0 = Clock::now();
    const GridPath path = p->plan({0.1, 0.1}, {19.99, 0.1}, o);
    const double ms = ms_since(t0);
    raiser.join();
    // Grid A* may finish (no path) before the flag rises; otherwise it must be CANCELLED, promptly.
    if (path.status != PlanStatus::kNoPath) {
      EXPECT_EQ(path.status, PlanStatus::kCancelled) << p->name();
      EXPECT_LT(ms, 10.0 + 100.0) << p->name();
    }
    // A flag already raised stops a query that would otherwise succeed.
    cancel.store(true);
    EXPECT_EQ(p->plan({0.1, 0.1}, {0.5, 0.5}, o).status, PlanStatus::kCancelled) << p->name();
  }
}

TEST_F(PlannerLimits, EveryGridPlannerHonoursItsNodeCap) {
  auto g = comb(6, 0.05);
  for (auto& p : all_grid_planners()) {
    p->set_grid(g);
    PlanOptions o;
    o.time_budget = std::chrono::seconds(10);
    o.node_cap = 3;
    const GridPath path = p->plan({0.5, 0.5}, {19.5, 0.5}, o);
    EXPECT_EQ(path.status, PlanStatus::kTimeout) << p->name();
  }
}

TEST_F(PlannerLimits, OccupiedStartOrGoalIsInvalidForEveryPlanner) {
  auto g = comb(6, 0.05);
  g->set(0, 0, true);
  for (auto& p : all_grid_planners()) {
    p->set_grid(g);
    EXPECT_EQ(p->plan({0.01, 0.01}, {19.5, 0.5}, {}).status, PlanStatus::kInvalidStart) << p->name();
    EXPECT_EQ(p->plan({0.5, 0.5}, {25.0, 0.5}, {}).status, PlanStatus::kInvalidStart) << p->name();
  }
}

}  // namespace
}  // namespace fleet::planning
