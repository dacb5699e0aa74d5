#pragma once

#include <deque>
#include <vector>

namespace fleet::coordination {

/// One robot's part of a plan: the places it passes from now on, its current place first, and the
/// step at which the plan has it enter each (0 for the current place).
struct PlannedRoute {
  std::vector<int> places;
  std::vector<int> entry_steps;
};

/// The order in which robots pass each place, fixed when a plan is loaded and kept however late
/// each robot runs: an action dependency graph [Hönig 2019, section IV]. A robot's visits follow
/// each other along its route (the graph's type-1 edges); at every place, a visit may begin only
/// once the visit planned before it there has ended (type-2 edges). Visits of a place are ordered
/// by the steps of a collision-free plan, so every dependency points from an earlier planned step
/// to a later one and the graph is acyclic: whatever the delays, some robot can always move, and
/// no two robots are ever in one place [Hönig 2019, section IV, the proof of deadlock freedom].
///
/// Places are plain numbers: grid cells here, conflict groups of a road map for vehicles with
/// footprints. Loading a new plan replaces every visit not yet begun; the plan must start where
/// the robots stand, which keeps the new graph acyclic too.
class ExecutionGraph {
 public:
  ExecutionGraph(int places, int robots);

  /// Replaces the plan. std::invalid_argument when a route is empty, its steps do not rise, a
  /// place is out of range, or two visits of one place are planned at the same step.
  void load(const std::vector<PlannedRoute>& routes);

  int robots() const { return static_cast<int>(routes_.size()); }
  int current_place(int robot) const;
  /// The place the robot enters next; -1 when its route is done.
  int next_place(int robot) const;
  /// The robot whose visit of `robot`'s next place comes before its own and has not ended; -1 when
  /// none does (the robot may enter), or when its route is done.
  int waits_for(int robot) const;
  /// The robot left its current place for its next one. std::logic_error when waits_for(robot)
  /// is not -1: the graph never lets a robot past a visit ordered before its own.
  void advance(int robot);
  /// Visits not yet begun, over all robots.
  int pending_visits() const;
  /// The robots of a wait-for cycle (each waits for the next), empty when there is none. A monitor:
  /// an acyclic graph has none, whatever the delays.
  std::vector<int> wait_cycle() const;

 private:
  struct Visit {
    int robot;
    int index;  ///< position in the robot's route
  };
  std::vector<PlannedRoute> routes_;
  std::vector<int> position_;                   ///< per robot: index of the place it stands in
  std::vector<std::deque<Visit>> place_queue_;  ///< per place: visits not ended, in planned order
};

}  // namespace fleet::coordination
