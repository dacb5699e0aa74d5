#include "coordination/window_lns.hpp"

#include <gtest/gtest.h>

#include <random>

#include "grid_plan_checks.hpp"

namespace fleet::coordination {
namespace {

using test::parse;

constexpr int kEast = 0;
constexpr int kWest = 2;

WindowPath standing(const GridRobot& robot, int horizon) {
  return {std::vector<int>(static_cast<std::size_t>(horizon) + 1, robot.cell),
          std::vector<int>(static_cast<std::size_t>(horizon) + 1, robot.heading)};
}

TEST(WindowLns, ALoneRobotIsGivenItsShortestWayInTheWindow) {
  const GridMap map = parse("......\n......\n", 2, 6);
  HeadingDistances distances(map);
  WindowLns lns(map, distances, 1);
  const std::vector<GridRobot> robots{{0, kEast, 9}};  // goal: row 1, column 3
  std::vector<WindowPath> plan{standing(robots[0], 8)};
  const long before = lns.cost(robots, plan);
  EXPECT_EQ(before, 8 + distances.to(9, 0, kEast));
  const long after = lns.improve(robots, plan, 5, 4);
  EXPECT_EQ(after, distances.to(9, 0, kEast));  // it arrives at the step its actions take
  EXPECT_EQ(lns.cost(robots, plan), after);
  EXPECT_EQ(plan[0].cells.back(), 9);
  std::string why;
  EXPECT_TRUE(WindowLns::valid(map, plan, &why)) << why;
}

TEST(WindowLns, ARobotWithoutAnErrandStepsIntoTheSidingForOneThatMustPass) {
  // A corridor with one siding cell below its middle, where a robot without an errand stands:
  // searched together, it steps aside and the other drives straight through.
  const GridMap map = parse(".......\n@@@.@@@\n", 2, 7);
  HeadingDistances distances(map);
  WindowLns lns(map, distances, 3);
  constexpr int kSouth = 1;
  const std::vector<GridRobot> robots{{1, kEast, 6}, {3, kSouth, -1}};
  std::vector<WindowPath> plan{standing(robots[0], 10), standing(robots[1], 10)};
  const long after = lns.improve(robots, plan, 50, 2);
  std::string why;
  ASSERT_TRUE(WindowLns::valid(map, plan, &why)) << why;
  EXPECT_EQ(after, 5);  // five moves, no wait
  EXPECT_EQ(plan[0].cells[5], 6);
  EXPECT_EQ(plan[1].cells.back(), 10);
}

TEST(WindowLns, ARobotThatHasStoodLongGoesElsewhereRatherThanStandOnBehindAHeldOne) {
  // A held robot stands in the only way to the goal: standing behind it costs least, until the
  // robot has stood so long that standing on costs more than backing away.
  const GridMap map = parse("......\n", 1, 6);
  HeadingDistances distances(map);
  std::vector<GridRobot> robots{{2, kEast, 5}, {3, kEast, -1}};
  robots[1].held = true;
  for (const int stood : {0, 30}) {
    WindowLns lns(map, distances, 5);
    lns.set_standstills({stood, 0});
    std::vector<WindowPath> plan{standing(robots[0], 6), standing(robots[1], 6)};
    const long before = lns.cost(robots, plan);
    EXPECT_EQ(before, 6 + distances.to(5, 2, kEast) + std::max(0, stood - 8));
    lns.improve(robots, plan, 20, 2);
    std::string why;
    ASSERT_TRUE(WindowLns::valid(map, plan, &why)) << why;
    if (stood == 0) {
      EXPECT_EQ(plan[0].cells.back(), 2) << "a robot that has not stood long waits behind the held one";
    } else {
      EXPECT_NE(plan[0].cells.back(), 2) << "a robot that has stood long goes elsewhere";
    }
  }
}

TEST(WindowLns, NeverRaisesTheCostAndKeepsEveryPlanValidInACrowdedRoom) {
  const GridMap map = parse("......\n.@..@.\n......\n..@...\n", 4, 6);
  HeadingDistances distances(map);
  std::vector<int> free;
  for (int c = 0; c < map.cells(); ++c) {
    if (map.is_free(c)) free.push_back(c);
  }
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 30; ++trial) {
    std::shuffle(free.begin(), free.end(), rng);
    std::vector<GridRobot> robots;
    std::vector<WindowPath> plan;
    for (int r = 0; r < 12; ++r) {
      GridRobot robot{free[static_cast<std::size_t>(r)], static_cast<int>(rng() % kHeadings),
                      r % 5 == 4 ? -1 : free[static_cast<std::size_t>((r * 7 + trial) % free.size())]};
      robot.held = r == 3;
      robots.push_back(robot);
      plan.push_back(standing(robot, 6));
    }
    WindowLns lns(map, distances, static_cast<std::uint64_t>(trial));
    const long before = lns.cost(robots, plan);
    const WindowPath held_path = plan[3];
    const long after = lns.improve(robots, plan, 40, 5);
    std::string why;
    ASSERT_TRUE(WindowLns::valid(map, plan, &why)) << "trial " << trial << ": " << why;
    EXPECT_LE(after, before) << "trial " << trial;
    EXPECT_EQ(after, lns.cost(robots, plan)) << "trial " << trial;
    EXPECT_EQ(plan[3].cells, held_path.cells) << "a held robot keeps its path";
    for (std::size_t r = 0; r < robots.size(); ++r) {
      EXPECT_EQ(plan[r].cells.front(), robots[r].cell);
      EXPECT_EQ(plan[r].headings.front(), robots[r].heading);
    }
  }
}

TEST(WindowLns, TheCheckNamesSharedCellsSwapsRingsAndMovesItDoesNotFace) {
  const GridMap map = parse("...\n...\n", 2, 3);
  std::string why;
  // Two robots swap cells 0 and 1.
  EXPECT_FALSE(WindowLns::valid(map, {{{0, 1}, {kEast, kEast}}, {{1, 0}, {kWest, kWest}}}, &why));
  EXPECT_EQ(why, "a swap or ring of robots");
  EXPECT_FALSE(WindowLns::valid(map, {{{0, 1}, {kEast, kEast}}, {{2, 1}, {kWest, kWest}}}, &why));
  EXPECT_EQ(why, "robots share a cell");
  // Four robots round the 2 x 2 square of cells 0, 1, 4, 3.
  constexpr int kSouth = 1;
  constexpr int kNorth = 3;
  EXPECT_FALSE(WindowLns::valid(
      map, {{{0, 1}, {kEast, kEast}}, {{1, 4}, {kSouth, kSouth}}, {{4, 3}, {kWest, kWest}}, {{3, 0}, {kNorth, kNorth}}},
      &why));
  EXPECT_EQ(why, "a swap or ring of robots");
  EXPECT_FALSE(WindowLns::valid(map, {{{0, 3}, {kEast, kEast}}}, &why));
  EXPECT_EQ(why, "robot 0 moves where it does not face");
  // Following into a cell left at the same step is allowed.
  EXPECT_TRUE(WindowLns::valid(map, {{{0, 1}, {kEast, kEast}}, {{1, 2}, {kEast, kEast}}}, &why)) << why;
}

}  // namespace
}  // namespace fleet::coordination
