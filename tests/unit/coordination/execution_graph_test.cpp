#include "coordination/execution_graph.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <stdexcept>

#include "coordination/grid_map.hpp"
#include "coordination/grid_pibt.hpp"
#include "coordination/heading_distances.hpp"

namespace fleet::coordination {
namespace {

PlannedRoute route(std::vector<int> places, std::vector<int> steps) {
  return {std::move(places), std::move(steps)};
}

TEST(ExecutionGraph, ARobotEntersAPlaceOnlyAfterTheVisitPlannedBeforeItsOwnHasEnded) {
  // Robot 0 crosses place 1 at step 1, robot 1 enters it at step 2: robot 1 waits for robot 0
  // however late robot 0 runs.
  ExecutionGraph graph(4, 2);
  graph.load({route({0, 1, 2}, {0, 1, 2}), route({3, 1}, {0, 2})});
  EXPECT_EQ(graph.waits_for(1), 0);
  EXPECT_THROW(graph.advance(1), std::logic_error);
  graph.advance(0);  // robot 0 enters place 1
  EXPECT_EQ(graph.waits_for(1), 0);
  graph.advance(0);  // and leaves it
  EXPECT_EQ(graph.waits_for(1), -1);
  graph.advance(1);
  EXPECT_EQ(graph.current_place(1), 1);
  EXPECT_EQ(graph.next_place(1), -1);
  EXPECT_EQ(graph.pending_visits(), 0);
  EXPECT_TRUE(graph.wait_cycle().empty());
}

TEST(ExecutionGraph, RefusesAPlanWithTwoRobotsEnteringOnePlaceAtOneStep) {
  ExecutionGraph graph(3, 2);
  EXPECT_THROW(graph.load({route({0, 2}, {0, 1}), route({1, 2}, {0, 1})}), std::invalid_argument);
  EXPECT_THROW(graph.load({route({0, 2}, {0, 0}), route({1}, {0})}), std::invalid_argument);
  EXPECT_THROW(graph.load({route({0, 5}, {0, 1}), route({1}, {0})}), std::invalid_argument);
  EXPECT_THROW(graph.load({route({0}, {0})}), std::invalid_argument);
}

TEST(ExecutionGraph, ReportsAWaitCycleOfAPlanThatIsNotCollisionFree) {
  // Two robots planned to swap places at one step: a plan no planner of Fleet makes, and the
  // monitor's reason to exist.
  ExecutionGraph graph(2, 2);
  graph.load({route({0, 1}, {0, 1}), route({1, 0}, {0, 2})});
  EXPECT_EQ(graph.waits_for(0), 1);
  EXPECT_EQ(graph.waits_for(1), 0);
  EXPECT_EQ(graph.wait_cycle().size(), 2u);
}

/// A small map with a dead end, a 2 x 2 room and a loop: the shapes where robots have to make
/// room for each other.
GridMap small_map() {
  GridMap map;
  map.rows = 5;
  map.cols = 6;
  const std::string cells =
      "......"
      ".@@.@."
      "......"
      ".@..@."
      "...@@.";
  for (char c : cells) map.free.push_back(c == '.' ? 1 : 0);
  map.source = "small";
  return map;
}

/// Plans with the planner, loads the plan into the graph, and lets robots enter in the graph's
/// order under a random delay schedule; asserts after every step that no two robots share a cell,
/// none swapped, and the graph has no wait cycle.
void run_with_delays(std::uint64_t seed, int robots, int window) {
  const GridMap map = small_map();
  HeadingDistances distances(map);
  GridPibt planner(map, distances, seed);
  ExecutionGraph graph(map.cells(), robots);
  std::mt19937_64 rng(seed);
  std::vector<int> free_cells;
  for (int c = 0; c < map.cells(); ++c) {
    if (map.is_free(c)) free_cells.push_back(c);
  }
  std::shuffle(free_cells.begin(), free_cells.end(), rng);
  std::vector<GridRobot> state(robots);
  for (int r = 0; r < robots; ++r) state[r] = {free_cells[r], 0, free_cells[(r + robots) % free_cells.size()]};
  int reached = 0;
  for (int step = 0; step < 300; ++step) {
    const auto cells = planner.plan(state, window);
    std::vector<PlannedRoute> routes(robots);
    for (int r = 0; r < robots; ++r) {
      for (std::size_t t = 0; t < cells[r].size(); ++t) {
        if (routes[r].places.empty() || routes[r].places.back() != cells[r][t]) {
          routes[r].places.push_back(cells[r][t]);
          routes[r].entry_steps.push_back(static_cast<int>(t));
        }
      }
    }
    ASSERT_NO_THROW(graph.load(routes)) << "seed " << seed << " step " << step;
    // A third of the robots are held this step, whatever the plan says; a robot that does not face
    // its next cell turns a quarter towards it; the others go in the graph's order.
    std::vector<int> ready;
    for (int r = 0; r < robots; ++r) {
      const int next = graph.next_place(r);
      if (next < 0 || std::uniform_int_distribution<int>(0, 2)(rng) == 0) continue;
      const int heading = map.heading_between(state[r].cell, next);
      if (heading == state[r].heading) {
        ready.push_back(r);
      } else {
        state[r].heading = (heading - state[r].heading + kHeadings) % kHeadings == 3
                               ? counter_clockwise(state[r].heading)
                               : clockwise(state[r].heading);
      }
    }
    const std::vector<GridRobot> before = state;
    for (bool moved = true; moved;) {
      moved = false;
      for (int& r : ready) {
        if (r < 0 || graph.waits_for(r) >= 0) continue;
        graph.advance(r);
        state[r].cell = graph.current_place(r);
        r = -1;
        moved = true;
      }
    }
    std::set<int> taken;
    for (int r = 0; r < robots; ++r) {
      ASSERT_TRUE(taken.insert(state[r].cell).second) << "two robots in one cell, seed " << seed << " step " << step;
      for (int o = 0; o < robots; ++o) {
        ASSERT_FALSE(o != r && state[r].cell == before[o].cell && state[o].cell == before[r].cell &&
                     state[r].cell != before[r].cell)
            << "robots " << r << " and " << o << " swapped, seed " << seed << " step " << step;
      }
    }
    ASSERT_TRUE(graph.wait_cycle().empty()) << "seed " << seed << " step " << step;
    for (int r = 0; r < robots; ++r) {
      if (graph.next_place(r) < 0 && state[r].cell != state[r].goal) {
        // Waiting: face the way with the fewest actions left, as a robot of Fleet does.
        const int h = state[r].heading;
        if (distances.to(state[r].goal, state[r].cell, clockwise(h)) < distances.to(state[r].goal, state[r].cell, h)) {
          state[r].heading = clockwise(h);
        } else if (distances.to(state[r].goal, state[r].cell, counter_clockwise(h)) <
                   distances.to(state[r].goal, state[r].cell, h)) {
          state[r].heading = counter_clockwise(h);
        }
      }
      if (state[r].cell == state[r].goal) {
        ++reached;
        planner.reached_goal(r);
        state[r].goal = free_cells[std::uniform_int_distribution<std::size_t>(0, free_cells.size() - 1)(rng)];
      }
    }
  }
  EXPECT_GT(reached, robots) << "seed " << seed << ": the robots kept moving";
}

TEST(ExecutionGraph, RandomDelaysOnASmallMapNeverCollideOrFormAWaitCycle) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    run_with_delays(seed, 4 + static_cast<int>(seed % 9), 1 + static_cast<int>(seed % 3));
  }
}

}  // namespace
}  // namespace fleet::coordination
