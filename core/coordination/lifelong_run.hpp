#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "coordination/execution_graph.hpp"
#include "coordination/grid_operation_pibt.hpp"
#include "coordination/grid_pibt.hpp"
#include "coordination/guide_paths.hpp"
#include "coordination/heading_distances.hpp"
#include "coordination/lorr_instance.hpp"
#include "coordination/window_lns.hpp"

namespace fleet::coordination {

/// The competition's actions: forward, clockwise, counter-clockwise, wait.
enum class GridAction : char { kForward = 'F', kClockwise = 'R', kCounterClockwise = 'C', kWait = 'W' };

/// Robots that stay put whatever they are told: at each step, a robot not already delayed is, with
/// probability `probability`, held for `min_steps`..`max_steps` steps (this one included).
struct DelayModel {
  double probability = 0.0;
  int min_steps = 1;
  int max_steps = 1;
};

/// How the planner chooses each robot's next steps: a next cell each (GridPibt) or a sequence of
/// actions each (GridOperationPibt).
enum class GridPlanner { kCells, kOperations };

/// The window a planner plans when none is given: 2 steps for cells, 3 actions for operations.
inline int default_window(GridPlanner planner) {
  return planner == GridPlanner::kCells ? 2 : 3;
}

struct LifelongSettings {
  int steps = 1000;
  GridPlanner planner = GridPlanner::kOperations;
  /// Steps the planner looks ahead each time it plans (re-planned every step); 0: the planner's
  /// own (2 for cells, 3 for operations).
  int window = 0;
  DelayModel delays;
  std::uint64_t seed = 1;
  /// Steer the operation planner's robots by congestion-avoiding guide paths (GuidePaths).
  bool guidance = true;
  /// The share of the robots whose guide paths are searched again each step, in turn, from where
  /// they stand and against the flow of the others' as it is by then.
  double guide_refine_share = 0.5;
  /// Steps of the window plan the operation planner's plan starts and large neighbourhood search
  /// improves (WindowLns); 0: no search, the operations' steps are the plan.
  int lns_window = 6;
  /// Neighbourhoods searched each step (0: 30 a robot), and robots in each.
  int lns_rounds = 0;
  int lns_size = 8;
};

/// One errand as the output lists it.
struct ErrandRecord {
  int id = 0;
  int cell = 0;
};
/// [errand id, step, "assigned" | "finished"], per robot, as the competition's output has them.
struct ErrandEvent {
  int errand = 0;
  int step = 0;
  bool finished = false;
};

/// What a run did, step by step and in sum.
struct LifelongResult {
  std::vector<std::string> actions;  ///< per robot: the action letter of every step
  std::vector<std::vector<ErrandEvent>> events;
  std::vector<ErrandRecord> errands;  ///< in the order they were handed out
  std::vector<double> planning_s;     ///< per step: planning and dependency-graph time
  std::vector<std::string> errors;    ///< collisions or swaps found by the step check (none expected)
  int finished = 0;
  int steps = 0;
  int longest_standstill = 0;  ///< most steps any robot with an errand kept its cell
  int wait_cycles = 0;         ///< steps at which the dependency graph held a wait-for cycle (none expected)
  long delayed_robot_steps = 0;
};

/// The League of Robot Runners' discrete world run by Fleet's coordination core: every step the
/// planner plans every robot's next cells together from where they stand, the plan is loaded into
/// the execution graph, and each robot turns towards its next cell or enters it once the graph lets
/// it (a robot may follow into a cell left in the same step, once the one ahead has moved). Delayed
/// robots stay put; those ordered behind them wait.
class LifelongGridRun {
 public:
  LifelongGridRun(const LorrInstance& instance, const LifelongSettings& settings);

  /// Runs every step and returns the record.
  const LifelongResult& run();
  /// Runs one step; false once all steps have run.
  bool step();
  const LifelongResult& result() const { return result_; }
  const std::vector<GridRobot>& robots() const { return robots_; }
  const ExecutionGraph& graph() const { return graph_; }

 private:
  void hand_out_errands();
  void update_guide_paths();
  std::vector<std::vector<int>> plan_window();
  void plan_and_load();
  std::vector<GridAction> decide_actions(const std::vector<bool>& stalled);
  GridAction turn_towards(int robot, int heading) const;
  GridAction best_turn_in_place(int robot);
  std::vector<bool> draw_delays();
  void apply(const std::vector<GridAction>& actions, const std::vector<int>& before);

  const LorrInstance& instance_;
  LifelongSettings settings_;
  HeadingDistances distances_;
  GridPibt cell_planner_;
  GridOperationPibt operation_planner_;
  GuidePaths guides_;
  WindowLns lns_;
  ExecutionGraph graph_;
  std::mt19937_64 delay_rng_;
  std::vector<GridRobot> robots_;
  std::vector<std::vector<ErrandRecord>> assigned_;  ///< per robot: errands known, first is its goal
  std::vector<int> handed_out_;                      ///< per robot: errands handed out so far
  std::vector<int> delay_left_;
  std::vector<int> still_for_;
  std::vector<bool> held_last_step_;  ///< robots seen standing still though told to move
  int next_errand_id_ = 0;
  int step_ = 0;
  LifelongResult result_;
};

/// A run's figures: errands finished a step, and the planning time a step (nearest-rank
/// percentiles of the per-step times, in milliseconds).
struct LifelongFigures {
  double throughput = 0.0;
  double planning_ms_p50 = 0.0;
  double planning_ms_p99 = 0.0;
  double planning_ms_max = 0.0;
};
LifelongFigures figures_of(const LifelongResult& result);

/// The competition's output file (the 2023 Start-Kit's `saveResults`, all details) of a run; the
/// executed actions go under both "plannerPaths" and "Planner Paths", the key the Start-Kit's
/// evaluation mode replays.
std::string lorr_output_json(const LorrInstance& instance, const LifelongResult& result);

}  // namespace fleet::coordination
