#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "coordination/grid_map.hpp"
#include "coordination/grid_pibt.hpp"
#include "coordination/guide_paths.hpp"
#include "coordination/heading_distances.hpp"

namespace fleet::coordination {

/// Priority inheritance with backtracking [Okumura 2022, Algorithm 1] over operations: each robot
/// chooses, in priority order, a sequence of `depth` actions (forward, quarter turns, waits) rather
/// than a next cell, so the quarter turns a move needs are planned with it and a robot pushed out
/// of the way can only leave the way it faces or after turning, as the League of Robot Runners 2024
/// winners' EPIBT does [LoRR 2024 EPIBT].
/// The operations are every action sequence of that length, those with the same cells and final
/// heading kept once. A robot's operations are tried cheapest first: one that reaches the goal
/// costs the steps it takes, any other the depth plus the actions left from where it ends
/// (HeadingDistances), then the least summed distance over its steps (progress early), then one
/// that pushes nobody, then the rest of its last operation.
///
/// Reservations are per cell and step of the window. A robot's operation must not put it in a cell
/// another planned robot holds at that step, swap cells with one, close a ring of robots each
/// moving into the next one's cell at one step, nor enter the cell of a robot whose own planning
/// is still in progress (it may fall back to standing there). It lends its priority to every
/// robot not yet planned that stands on its cells: each must plan an operation clear of it, or
/// the robot tries its next operation; a robot that cannot get out stays.
///
/// The result is the cells of every robot for steps 0..depth, with no two robots in one cell at
/// a step, no swaps and no rings: an execution graph loads it acyclic.
class GridOperationPibt {
 public:
  GridOperationPibt(const GridMap& map, HeadingDistances& distances, std::uint64_t seed);

  /// Every robot's cells for steps 0..depth (step 0: where it stands).
  std::vector<std::vector<int>> plan(const std::vector<GridRobot>& robots, int depth);
  /// A robot's headings for steps 0..depth by the operation planned for it at the last plan.
  std::vector<int> planned_headings(int robot) const;
  /// Tells the planner a robot reached its goal: its priority starts over.
  void reached_goal(int robot);
  /// Steers robots by their guide paths instead of the shortest way (nullptr: the shortest way).
  void set_guide_paths(const GuidePaths* guides) { guides_ = guides; }
  /// The action letters of the operations for a depth (each effect once), cheapest to list first.
  static std::vector<std::string> operations(int depth);

 private:
  struct Trace {
    std::vector<int> cells;     ///< steps 0..depth
    std::vector<int> headings;  ///< steps 0..depth
  };
  /// The cells and headings an operation takes a robot through; false when it drives into a wall.
  bool trace(const GridRobot& robot, const std::string& operation, Trace& out) const;
  /// Plans a robot; `leave_by` > 0: it is pushed and must be out of its cell by that step.
  bool plan_robot(int robot, int leave_by);
  /// Whether robot may take the trace given the reservations; lists the unplanned robots it pushes
  /// and the step at which it enters each one's cell.
  bool admissible(int robot, const Trace& t, std::vector<int>& pushed, std::vector<int>& entry_steps) const;
  bool closes_ring(int robot, const Trace& t, int step) const;
  void reserve(int robot, const Trace& t);
  void release(int robot);
  void stay(int robot);
  /// Actions left for a robot from (cell, heading): by its guide path when it has one to its goal.
  int actions_left(int robot, int cell, int heading);
  int holder(int step, int cell) const { return held_[static_cast<std::size_t>(step) * cells_ + cell]; }

  const GridMap& map_;
  HeadingDistances& distances_;
  const GuidePaths* guides_ = nullptr;
  std::mt19937_64 rng_;
  std::vector<std::string> operations_;
  int depth_ = 0;
  std::size_t cells_ = 0;
  std::vector<double> priority_;
  std::vector<GridRobot> robots_;
  std::vector<int> standing_;           ///< per cell: the robot standing there now, -1
  std::vector<int> held_;               ///< per step and cell: the planned robot there, -1
  std::vector<std::vector<int>> path_;  ///< per robot: its planned cells, empty while unplanned
  std::vector<std::uint8_t> planning_;  ///< per robot: its planning is in progress
  std::vector<std::string> last_;       ///< per robot: the operation it was planned last step
  std::vector<std::string> chosen_;     ///< per robot: this step's operation
  std::vector<int> last_cell_;          ///< per robot: its cell at the last plan
  std::vector<int> still_;              ///< per robot: plans in a row it stood in one cell
  std::vector<int> cannot_leave_by_;    ///< per robot: pushed, it could not leave by this step
  long pushes_left_ = 0;
};

}  // namespace fleet::coordination
