#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "coordination/grid_map.hpp"
#include "coordination/heading_distances.hpp"

namespace fleet::coordination {

/// A robot on a grid as the planner sees it.
struct GridRobot {
  int cell = 0;
  int heading = 0;
  int goal = -1;      ///< -1: no errand, the robot only keeps out of the way
  bool held = false;  ///< it stood still last step though told to move: planned to stay where it is
};

/// Priority inheritance with backtracking [Okumura 2022, Algorithm 1], planning every robot's next
/// cell together, one step at a time, for a window of steps. A robot's candidates are its cell and
/// its free neighbours, cheapest first by the actions left to its goal counting the quarter turns;
/// a robot that wants a cell another stands on lends that one its priority, and the one pushed
/// must move out or the first tries its next candidate. The robot that has waited longest since
/// its last goal goes first. When the robot standing in its best cell cannot move out, a robot
/// steps aside rather than wait: that is how one in a dead end gets out past one that wants its
/// cell.
///
/// A robot that chose a cell it must turn to first keeps that cell for the steps the turn takes
/// (and one more to drive in): choosing afresh every step would have robots turn one way and the
/// other and never drive. A robot standing in a dead end goes before others.
///
/// Two rules make the plan fit execution through an acyclic dependency graph: no two robots swap
/// cells, and no robots move round a cycle of cells in one step (each would wait for the one ahead
/// to leave).
class GridPibt {
 public:
  GridPibt(const GridMap& map, HeadingDistances& distances, std::uint64_t seed);

  /// The cells of every robot for steps 0..window (step 0: where it stands), collision-free: no two
  /// robots in one cell at one step, no swaps, no cycles. A move that needs the robot to turn first
  /// counts one step per quarter turn in later windows' headings.
  std::vector<std::vector<int>> plan(const std::vector<GridRobot>& robots, int window);
  /// Tells the planner which robots reached their goal in the last step: their priority starts over.
  void reached_goal(int robot);

 private:
  bool plan_robot(int robot, int pusher);
  /// Actions left to the goal by way of `cell`, entered facing `heading`.
  int candidate_cost(int robot, int cell, int heading) const;
  bool closes_cycle(int robot, int cell) const;
  void plan_one_step(bool keep_commitments);
  void commit(const std::vector<GridRobot>& robots);
  void keep_commitment(int robot, int cell);

  const GridMap& map_;
  HeadingDistances& distances_;
  std::mt19937_64 rng_;
  std::vector<double> priority_;
  std::vector<GridRobot> robots_;  ///< the state being planned from
  std::vector<int> now_;           ///< per cell: the robot standing there, -1
  std::vector<int> next_;          ///< per cell: the robot planned there next step, -1
  std::vector<int> planned_;       ///< per robot: its cell next step, -1 while not planned
  std::vector<int> order_;
  std::vector<int> committed_;      ///< per robot: the cell it turned towards and has not reached, -1
  std::vector<int> committed_for_;  ///< per robot: steps it has held that cell
};

}  // namespace fleet::coordination
