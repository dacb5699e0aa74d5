#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "coordination/grid_map.hpp"
#include "coordination/grid_pibt.hpp"
#include "coordination/guide_paths.hpp"
#include "coordination/heading_distances.hpp"

namespace fleet::coordination {

/// A robot's planned states in a window: cell and heading at steps 0..H.
struct WindowPath {
  std::vector<int> cells;
  std::vector<int> headings;
};

/// Improves a window plan of every robot's moves by large neighbourhood search [Li 2021b, section
/// 4]: a few robots near one another are taken out of the plan and searched again, one at a time
/// in a random order, by space-time A* over (cell, heading, step) round the paths of all the
/// others; the new paths are kept when their summed cost is lower, otherwise the old ones are put
/// back. The window is the rolling horizon of [Li 2021, section 4]: the plan covers H steps and
/// only the first is carried out before the robots are planned again.
///
/// A neighbourhood is a late robot and the robots whose paths lie on its way to its goal: the
/// agent-based neighbourhood of [Li 2021b, section 4], the robots that keep it late.
///
/// A path's cost is the step at which it reaches the robot's goal, or H plus the actions left
/// from where it ends when it does not (by the guide path when the robot has one). A plan is
/// valid when no two robots are in one cell at a step, no two swap cells, and no ring of robots
/// each enters the cell the next one leaves at one step (the execution graph orders the rest).
class WindowLns {
 public:
  WindowLns(const GridMap& map, HeadingDistances& distances, std::uint64_t seed);

  /// Steers the cost by guide paths (nullptr: the shortest way).
  void set_guide_paths(const GuidePaths* guides) { guides_ = guides; }
  /// Steps each robot has stood in its cell with an errand: a path that ends where it has stood
  /// long costs more for each step beyond eight (unset: nothing).
  void set_standstills(const std::vector<int>& stood) { stood_ = stood; }
  /// Improves a valid plan for `robots` by `neighbourhoods` searches of at most `size` robots;
  /// a held robot keeps its path. Returns the plan's summed cost.
  long improve(const std::vector<GridRobot>& robots, std::vector<WindowPath>& plan, int neighbourhoods, int size);
  /// The summed cost of a plan.
  long cost(const std::vector<GridRobot>& robots, const std::vector<WindowPath>& plan);
  /// Whether a plan keeps the rules above; `why` says which rule it breaks first.
  static bool valid(const GridMap& map, const std::vector<WindowPath>& plan, std::string* why = nullptr);

 private:
  int path_cost(int robot, const WindowPath& path);
  int standing_penalty(int robot, int end_cell) const;
  int actions_left(int robot, int cell, int heading);
  void occupy(int robot, const WindowPath& path);
  void vacate(int robot, const WindowPath& path);
  int at(int step, int cell) const { return occupied_[static_cast<std::size_t>(step) * cells_ + cell]; }
  bool closes_ring(int robot, int from, int to, int step) const;
  /// Space-time A* for one robot round the occupied cells; false when no path keeps the rules.
  bool search(int robot, WindowPath& out);
  int draw_late_robot(const std::vector<int>& movable, const std::vector<int>& costs, const std::vector<int>& least);
  std::vector<int> neighbourhood(int seed_robot, int size);
  /// Adds the robots whose paths pass `cell` in the window, up to `size` in all.
  void add_passing(int cell, std::vector<int>& group, int size);

  const GridMap& map_;
  HeadingDistances& distances_;
  const GuidePaths* guides_ = nullptr;
  std::mt19937_64 rng_;
  std::size_t cells_ = 0;
  int horizon_ = 0;
  std::vector<GridRobot> robots_;
  std::vector<int> stood_;
  std::vector<WindowPath>* plan_ = nullptr;
  std::vector<int> occupied_;  ///< per step and cell: the robot there, -1
  // The search's tables, kept between searches: per (step, cell, heading) state.
  std::vector<int> best_g_;
  std::vector<int> parent_;
  std::vector<std::uint32_t> seen_;
  std::uint32_t stamp_ = 0;
  // The cells and robots a neighbourhood has taken in, by stamp, kept between neighbourhoods.
  std::vector<std::uint32_t> reached_;   ///< per cell
  std::vector<std::uint32_t> in_group_;  ///< per robot
  std::uint32_t reach_stamp_ = 0;
};

}  // namespace fleet::coordination
