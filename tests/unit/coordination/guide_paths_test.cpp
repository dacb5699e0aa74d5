#include "coordination/guide_paths.hpp"

#include <gtest/gtest.h>

#include "coordination/heading_distances.hpp"
#include "grid_plan_checks.hpp"

namespace fleet::coordination {
namespace {

using test::parse;

constexpr int kEast = 0;
constexpr int kWest = 2;

int cell_at(const GridMap& map, int row, int col) {
  return row * map.cols + col;
}

TEST(GuidePaths, AloneARobotIsGuidedTheShortestWayWithTheFewestTurns) {
  const GridMap map = parse(".....\n.....\n.....\n", 3, 5);
  GuidePaths guides(map, 1);
  HeadingDistances distances(map);
  const int from = cell_at(map, 0, 0);
  const int goal = cell_at(map, 2, 4);
  guides.assign(0, from, kEast, goal);
  const auto& path = guides.path(0);
  ASSERT_FALSE(path.empty());
  EXPECT_EQ(path.front(), from);
  EXPECT_EQ(path.back(), goal);
  EXPECT_EQ(path.size(), 7u);  // 6 moves
  // Its heuristic from where it stands is the exact one: six moves and one quarter turn, not a
  // staircase of turns.
  EXPECT_EQ(guides.to(0, from, kEast), distances.to(goal, from, kEast));
  EXPECT_EQ(guides.to(0, from, kEast), 7);
  for (int h = 0; h < kHeadings; ++h) EXPECT_EQ(guides.to(0, goal, h), 0);
}

TEST(GuidePaths, TheHeuristicFallsByOneForEachActionAlongThePath) {
  const GridMap map = parse("......\n.@@@@.\n......\n", 3, 6);
  GuidePaths guides(map, 1);
  const int from = cell_at(map, 0, 0);
  guides.assign(0, from, kEast, cell_at(map, 2, 0));
  const auto& path = guides.path(0);
  ASSERT_GE(path.size(), 3u);
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const int heading = map.heading_between(path[i], path[i + 1]);
    const int next_heading = i + 2 < path.size() ? map.heading_between(path[i + 1], path[i + 2]) : heading;
    // Standing on the path facing its way, the actions left are the cells left and the turns.
    EXPECT_EQ(guides.to(0, path[i], heading),
              guides.to(0, path[i + 1], next_heading) + 1 + quarter_turns(heading, next_heading))
        << "at path cell " << i;
  }
}

TEST(GuidePaths, ARobotGoingTheOtherWayIsGuidedRoundTheOthersStream) {
  // Two corridors of equal length between the east and west ends: a robot going west is guided
  // along the corridor the robot going east does not use.
  const GridMap map = parse("........\n.@@@@@@.\n........\n", 3, 8);
  GuidePaths guides(map, 2);
  const int west = cell_at(map, 1, 0);
  const int east = cell_at(map, 1, 7);
  guides.assign(0, west, kEast, east);
  const bool top = guides.path(0)[2] / map.cols == 0;
  guides.assign(1, east, kWest, west);
  EXPECT_EQ(guides.path(1)[2] / map.cols, top ? 2 : 0);
  EXPECT_EQ(guides.contraflow(), 0);
  // Searched again from their ends, each keeps its corridor.
  guides.refine({west, east}, {kEast, kWest}, 2);
  EXPECT_EQ(guides.path(0)[2] / map.cols, top ? 0 : 2);
  EXPECT_EQ(guides.path(1)[2] / map.cols, top ? 2 : 0);
}

TEST(GuidePaths, ThePathBehindARobotStopsCountingAndAGoalOfNoneClearsIt) {
  const GridMap map = parse("....\n", 1, 4);
  GuidePaths guides(map, 2);
  guides.assign(0, 0, kEast, 3);
  EXPECT_EQ(guides.flow(0, kEast), 1);
  EXPECT_EQ(guides.flow(1, kEast), 1);
  guides.advance(0, 2);
  EXPECT_EQ(guides.flow(0, kEast), 0);
  EXPECT_EQ(guides.flow(1, kEast), 0);
  EXPECT_EQ(guides.flow(2, kEast), 1);
  guides.assign(1, 3, kWest, 0);
  EXPECT_EQ(guides.contraflow(), 1);  // one lane: the only way, against the first robot's
  guides.assign(0, 2, kEast, -1);
  EXPECT_FALSE(guides.has_path(0));
  EXPECT_EQ(guides.flow(2, kEast), 0);
  EXPECT_EQ(guides.contraflow(), 0);
  // Searched again from where they stand, paths keep their goals.
  guides.refine({2, 2}, {kEast, kWest}, 2);
  EXPECT_EQ(guides.goal(1), 0);
  EXPECT_EQ(guides.path(1).front(), 2);
  EXPECT_FALSE(guides.has_path(0));
}

TEST(GuidePaths, AGoalOutOfReachGivesNoPath) {
  const GridMap map = parse("..@..\n", 1, 5);
  GuidePaths guides(map, 1);
  guides.assign(0, 0, kEast, 4);
  EXPECT_FALSE(guides.has_path(0));
  EXPECT_EQ(guides.to(0, 0, kEast), GuidePaths::kUnreachable);
}

}  // namespace
}  // namespace fleet::coordination
