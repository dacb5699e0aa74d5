#include "coordination/grid_operation_pibt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "coordination/grid_map.hpp"
#include "coordination/heading_distances.hpp"
#include "grid_plan_checks.hpp"

namespace fleet::coordination {
namespace {

using test::expect_executable;
using test::parse;

TEST(GridOperationPibt, ListsEachEffectOnceWithTheFewestTurns) {
  const std::vector<std::string> ops = GridOperationPibt::operations(3);
  // 64 sequences; those that turn one way and back, or waste turns, do what another does.
  EXPECT_LT(ops.size(), 64u);
  EXPECT_GT(ops.size(), 20u);
  EXPECT_NE(std::find(ops.begin(), ops.end(), "FFF"), ops.end());
  EXPECT_NE(std::find(ops.begin(), ops.end(), "WWW"), ops.end());
  EXPECT_NE(std::find(ops.begin(), ops.end(), "RRF"), ops.end());  // turn round, then drive back
  EXPECT_EQ(std::find(ops.begin(), ops.end(), "RCW"), ops.end());  // the same as WWW
  EXPECT_EQ(std::find(ops.begin(), ops.end(), "RWC"), ops.end());
}

TEST(GridOperationPibt, PlansAreFreeOfCollisionsSwapsAndRingsAndFollowTheRobotsHeadings) {
  const GridMap map = parse(".......\n.@.@.@.\n.......\n.@.@.@.\n.......\n", 5, 7);
  HeadingDistances distances(map);
  std::vector<int> free_cells;
  for (int c = 0; c < map.cells(); ++c) {
    if (map.is_free(c)) free_cells.push_back(c);
  }
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    std::mt19937_64 rng(seed);
    std::shuffle(free_cells.begin(), free_cells.end(), rng);
    const int robots = 5 + static_cast<int>(seed % 22);
    std::vector<GridRobot> state(static_cast<std::size_t>(robots));
    for (int r = 0; r < robots; ++r) {
      state[r] = {free_cells[r], static_cast<int>(rng() % 4), free_cells[(r + 7) % free_cells.size()], rng() % 5 == 0};
    }
    GridOperationPibt planner(map, distances, seed);
    // Several plans in a row, each robot carried one step along its own: the planner's memory of
    // the last operations and of robots standing still is exercised too.
    for (int round = 0; round < 6; ++round) {
      const auto cells = planner.plan(state, 3);
      ASSERT_EQ(cells.size(), static_cast<std::size_t>(robots));
      for (int step = 1; step <= 3; ++step) expect_executable(cells, step);
      for (int r = 0; r < robots; ++r) {
        if (state[r].held) {
          for (int step = 1; step <= 3; ++step) ASSERT_EQ(cells[r][step], state[r].cell) << "held robot " << r;
        }
        // A robot moves only the way it faces, or stays a step for each quarter turn.
        const int first_move = cells[r][1];
        if (first_move != state[r].cell) {
          ASSERT_EQ(map.heading_between(state[r].cell, first_move), state[r].heading);
        }
      }
      for (int r = 0; r < robots; ++r) {
        if (cells[r][1] != state[r].cell) state[r].cell = cells[r][1];
        state[r].held = false;
      }
    }
  }
}

TEST(GridOperationPibt, ARobotFacingAwayTurnsRoundBeforeItMoves) {
  // A corridor: the robot faces east, its goal is two cells west.
  const GridMap map = parse(".....\n", 1, 5);
  HeadingDistances distances(map);
  GridOperationPibt planner(map, distances, 1);
  const auto cells = planner.plan({{2, 0, 0}}, 3);
  EXPECT_EQ(cells[0], (std::vector<int>{2, 2, 2, 1}));
}

TEST(GridOperationPibt, ARobotFollowsIntoTheCellTheOneAheadLeavesAtTheSameStep) {
  // Two robots in line facing east, both bound for the east end of the lower row: whichever plans
  // first, the one ahead drives on and the one behind follows at once.
  const GridMap map = parse("......\n......\n", 2, 6);
  HeadingDistances distances(map);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    GridOperationPibt planner(map, distances, seed);
    const auto cells = planner.plan({{6, 0, 11}, {7, 0, 11}}, 3);
    EXPECT_EQ(cells[0], (std::vector<int>{6, 7, 8, 9})) << "seed " << seed;
    EXPECT_EQ(cells[1], (std::vector<int>{7, 8, 9, 10})) << "seed " << seed;
  }
}

}  // namespace
}  // namespace fleet::coordination
