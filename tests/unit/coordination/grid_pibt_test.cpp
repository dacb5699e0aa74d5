#include "coordination/grid_pibt.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "coordination/grid_map.hpp"
#include "coordination/heading_distances.hpp"
#include "grid_plan_checks.hpp"

namespace fleet::coordination {
namespace {

using test::expect_executable;
using test::parse;

TEST(GridPibt, PlansAreFreeOfCollisionsSwapsAndRings) {
  const GridMap map = parse(".......\n.@.@.@.\n.......\n.@.@.@.\n.......\n", 5, 7);
  HeadingDistances distances(map);
  std::vector<int> free_cells;
  for (int c = 0; c < map.cells(); ++c) {
    if (map.is_free(c)) free_cells.push_back(c);
  }
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    std::mt19937_64 rng(seed);
    std::shuffle(free_cells.begin(), free_cells.end(), rng);
    const int robots = 5 + static_cast<int>(seed % 20);
    std::vector<GridRobot> state(robots);
    for (int r = 0; r < robots; ++r) {
      state[r] = {free_cells[r], static_cast<int>(rng() % 4), free_cells[(r + 7) % free_cells.size()]};
    }
    GridPibt planner(map, distances, seed);
    const auto cells = planner.plan(state, 3);
    ASSERT_EQ(cells.size(), static_cast<std::size_t>(robots));
    for (int step = 1; step <= 3; ++step) expect_executable(cells, step);
  }
}

TEST(GridPibt, TheRobotInADeadEndGetsOutPastOneThatWantsItsCell) {
  // Robot 0 stands at the end of a dead end (cell 0) and must leave through cell 1, where robot 1
  // stands and whose goal is cell 0: robot 1 steps aside into the side corridor.
  const GridMap map = parse("....\n@.@@\n@.@@\n", 3, 4);
  HeadingDistances distances(map);
  GridPibt planner(map, distances, 3);
  std::vector<GridRobot> state{{0, 0, 3}, {1, 2, 0}};
  bool swapped = false;
  for (int step = 0; step < 20 && !swapped; ++step) {
    const auto cells = planner.plan(state, 1);
    // A move the robot does not face is a quarter turn this step; a robot that waits faces its
    // goal's way; a robot moves into the other's cell only once that one has left it.
    bool moves[2];
    for (int r = 0; r < 2; ++r) {
      GridRobot& robot = state[r];
      moves[r] = false;
      if (cells[r][1] != robot.cell) {
        const int heading = map.heading_between(robot.cell, cells[r][1]);
        moves[r] = heading == robot.heading;
        if (!moves[r]) {
          robot.heading = (heading - robot.heading + kHeadings) % kHeadings == 3 ? counter_clockwise(robot.heading)
                                                                                 : clockwise(robot.heading);
        }
      } else {
        for (int h : {clockwise(robot.heading), counter_clockwise(robot.heading)}) {
          if (distances.to(robot.goal, robot.cell, h) < distances.to(robot.goal, robot.cell, robot.heading)) {
            robot.heading = h;
          }
        }
      }
    }
    for (int r : {0, 1, 0, 1}) {
      if (moves[r] && cells[r][1] != state[1 - r].cell) {
        state[r].cell = cells[r][1];
        moves[r] = false;
      }
    }
    ASSERT_NE(state[0].cell, state[1].cell);
    swapped = state[0].cell != 0 && state[0].cell != 1 && state[1].cell <= 1;
  }
  EXPECT_TRUE(swapped) << "robot 0 at " << state[0].cell << ", robot 1 at " << state[1].cell;
}

TEST(GridPibt, AHeldRobotStaysInThePlanAndNoOneIsPlannedIntoItsCell) {
  // A corridor of five cells with a loop above: robot 0, held in the middle, is in robot 1's way.
  const GridMap map = parse(".....\n.@@@.\n.....\n", 3, 5);
  HeadingDistances distances(map);
  GridPibt planner(map, distances, 1);
  const std::vector<GridRobot> state{{12, 0, 14, true}, {11, 0, 14, false}, {13, 2, 10, false}};
  const auto cells = planner.plan(state, 3);
  for (int step = 1; step <= 3; ++step) {
    EXPECT_EQ(cells[0][step], 12) << "step " << step;
    EXPECT_NE(cells[1][step], 12) << "step " << step;
    EXPECT_NE(cells[2][step], 12) << "step " << step;
  }
}

}  // namespace
}  // namespace fleet::coordination
