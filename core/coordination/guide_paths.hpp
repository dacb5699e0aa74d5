#pragma once

#include <cstdint>
#include <vector>

#include "coordination/grid_map.hpp"
#include "coordination/heading_distances.hpp"

namespace fleet::coordination {

/// Congestion-avoiding guide paths [Chen 2024, guide paths]: every robot with an errand keeps a
/// path of cells to its goal, searched over a map whose moves cost more where other robots'
/// guide paths run against them (contraflow) or crowd a cell (vertex congestion), so streams of
/// robots are spread over the map and do not meet head-on in its passages. The planner then
/// steers each robot by the actions to its guide path and along it, not by the shortest way.
///
/// A move u -> v costs 1 + 2 (f(u->v) + 1) f(v->u) + (sum of the flows out of v) / 2, f counting
/// the guide paths of the other robots that make that move (the paper weighs contraflow once;
/// twice finishes more errands on the competition's maps); a quarter turn costs 1. A robot's heuristic is, from every
/// (cell, heading), the fewest actions to some cell of its path plus the path's cells left from
/// there, the nearest path cell taken (ties to the one nearer the goal) [Chen 2024, Guided PIBT].
/// The weights of a move's cost: 1 + contraflow (f(u->v) + 1) f(v->u) + crowd_percent/100 of the
/// flows out of v. The defaults suit the operation planner alone: on the League of Robot Runners'
/// random-32-32-20 (seeds 1-3), twice the paper's contraflow weight finishes 4 % more errands a
/// step than once with 200 robots and 9 % more with 400, four times no more than twice. Under the
/// window search, which settles meetings itself, the lighter kWindowSearchWeights finish more.
struct GuideWeights {
  int contraflow = 2;
  int crowd_percent = 50;
};
inline constexpr GuideWeights kWindowSearchWeights{1, 25};

class GuidePaths {
 public:
  static constexpr std::uint16_t kUnreachable = 0xFFFF;

  GuidePaths(const GridMap& map, int robots);

  /// Sets the move costs' weights for the paths searched from now on.
  void set_weights(const GuideWeights& weights) { weights_ = weights; }

  /// Gives `robot` a new guide path from `cell`, facing `heading`, to `goal` (goal < 0: none),
  /// replacing its old one.
  void assign(int robot, int cell, int heading, int goal);
  /// The robot stands at `cell`: the cells of its path it has passed stop counting as its flow.
  void advance(int robot, int cell);
  /// Searches `count` robots' paths again from where they stand (`cells`, `headings`, per robot),
  /// against the others' flow as it is by then, taking the robots with a goal in turn: the flow a
  /// path was searched against changes as the others get new goals.
  void refine(const std::vector<int>& cells, const std::vector<int>& headings, int count);

  /// Actions left for `robot` from (cell, heading) by way of its guide path.
  int to(int robot, int cell, int heading) const {
    return field_[static_cast<std::size_t>(robot)][static_cast<std::size_t>(cell) * kHeadings + heading];
  }
  bool has_path(int robot) const { return !path_[static_cast<std::size_t>(robot)].empty(); }
  const std::vector<int>& path(int robot) const { return path_[static_cast<std::size_t>(robot)]; }
  int goal(int robot) const { return goal_[static_cast<std::size_t>(robot)]; }
  /// The guide paths' flow on the move from `cell` towards `heading`.
  int flow(int cell, int heading) const { return flow_[static_cast<std::size_t>(cell) * kHeadings + heading]; }
  /// Summed over every move: f(u->v) f(v->u), the contraflow the paths leave.
  long contraflow() const;

 private:
  std::vector<int> search(int from, int heading, int goal) const;
  int move_cost(int cell, int heading) const;
  void add_flow(int robot, int sign);
  void build_field(int robot);

  const GridMap& map_;
  GuideWeights weights_;
  std::vector<std::uint16_t> flow_;                ///< per cell x heading
  std::vector<std::vector<int>> path_;             ///< per robot: cells, start to goal
  std::vector<std::size_t> passed_;                ///< per robot: path cells behind it
  std::vector<int> goal_;                          ///< per robot
  std::vector<std::vector<std::uint16_t>> field_;  ///< per robot: cell x heading
  std::size_t next_refined_ = 0;
};

/// Actions left for `robot` from (cell, heading) to `goal`: by its guide path when `guides` has one
/// to that goal, the shortest way otherwise.
inline int actions_to_goal(const GuidePaths* guides, HeadingDistances& distances, int robot, int goal, int cell,
                           int heading) {
  if (guides != nullptr && guides->goal(robot) == goal && guides->has_path(robot)) {
    return guides->to(robot, cell, heading);
  }
  return distances.to(goal, cell, heading);
}

}  // namespace fleet::coordination
