#include "coordination/lifelong_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/percentile.hpp"

namespace fleet::coordination {

namespace {

/// Neighbourhoods the window search tries a step, per robot: 12 000 with 400 robots take a
/// median of 0.12 s a step on 2 cores, a tenth of the competition's second.
constexpr int kWindowSearchRoundsPerRobot = 30;

}  // namespace

LifelongGridRun::LifelongGridRun(const LorrInstance& instance, const LifelongSettings& settings)
    : instance_(instance),
      settings_(settings),
      distances_(instance.map),
      cell_planner_(instance.map, distances_, settings.seed),
      operation_planner_(instance.map, distances_, settings.seed),
      guides_(instance.map, static_cast<int>(instance.starts.size())),
      lns_(instance.map, distances_, settings.seed + 1),
      graph_(instance.map.cells(), static_cast<int>(instance.starts.size())),
      delay_rng_(settings.seed * 0x9E3779B97F4A7C15ULL + 1) {
  if (settings_.window <= 0) settings_.window = default_window(settings_.planner);
  if (settings_.lns_rounds <= 0)
    settings_.lns_rounds = kWindowSearchRoundsPerRobot * static_cast<int>(instance.starts.size());
  if (settings_.lns_window > 0) guides_.set_weights(kWindowSearchWeights);
  if (settings_.guidance && settings_.planner == GridPlanner::kOperations) {
    operation_planner_.set_guide_paths(&guides_);
    lns_.set_guide_paths(&guides_);
  }
  const std::size_t n = instance.starts.size();
  robots_.resize(n);
  for (std::size_t i = 0; i < n; ++i) robots_[i] = {instance.starts[i], 0, -1};
  assigned_.resize(n);
  handed_out_.assign(n, 0);
  delay_left_.assign(n, 0);
  still_for_.assign(n, 0);
  held_last_step_.assign(n, false);
  result_.actions.resize(n);
  result_.events.resize(n);
  hand_out_errands();
}

void LifelongGridRun::hand_out_errands() {
  const int team = static_cast<int>(robots_.size());
  const int tasks = static_cast<int>(instance_.tasks.size());
  for (int r = 0; r < team; ++r) {
    while (static_cast<int>(assigned_[r].size()) < instance_.tasks_revealed) {
      const long line = static_cast<long>(handed_out_[r]) * team + r;
      const ErrandRecord errand{next_errand_id_++, instance_.tasks[static_cast<std::size_t>(line % tasks)]};
      assigned_[r].push_back(errand);
      result_.errands.push_back(errand);
      result_.events[r].push_back({errand.id, step_, false});
      ++handed_out_[r];
    }
    robots_[r].goal = assigned_[r].front().cell;
  }
}

void LifelongGridRun::update_guide_paths() {
  if (!settings_.guidance || settings_.planner != GridPlanner::kOperations) return;
  std::vector<int> cells(robots_.size());
  std::vector<int> headings(robots_.size());
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    const GridRobot& robot = robots_[r];
    cells[r] = robot.cell;
    headings[r] = robot.heading;
    if (guides_.goal(static_cast<int>(r)) != robot.goal) {
      guides_.assign(static_cast<int>(r), robot.cell, robot.heading, robot.goal);
    } else {
      guides_.advance(static_cast<int>(r), robot.cell);
    }
  }
  const int refines = std::max(1, static_cast<int>(std::lround(settings_.guide_refine_share * robots_.size())));
  guides_.refine(cells, headings, refines);
}

std::vector<std::vector<int>> LifelongGridRun::plan_window() {
  auto cells = operation_planner_.plan(robots_, settings_.window);
  const int horizon = settings_.lns_window;
  if (horizon <= 0 || horizon < settings_.window) return cells;
  // The operations' steps, standing after them to the window's end, start the search.
  const std::size_t n = robots_.size();
  std::vector<WindowPath> plan(n);
  for (std::size_t r = 0; r < n; ++r) {
    WindowPath& path = plan[r];
    path.cells = cells[r];
    path.headings = operation_planner_.planned_headings(static_cast<int>(r));
    path.cells.resize(static_cast<std::size_t>(horizon) + 1, path.cells.back());
    path.headings.resize(static_cast<std::size_t>(horizon) + 1, path.headings.back());
  }
  lns_.set_standstills(still_for_);
  lns_.improve(robots_, plan, settings_.lns_rounds, settings_.lns_size);
  for (std::size_t r = 0; r < n; ++r) cells[r] = plan[r].cells;
  return cells;
}

void LifelongGridRun::plan_and_load() {
  const auto cells =
      settings_.planner == GridPlanner::kCells ? cell_planner_.plan(robots_, settings_.window) : plan_window();
  std::vector<PlannedRoute> routes(robots_.size());
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    PlannedRoute& route = routes[r];
    for (std::size_t t = 0; t < cells[r].size(); ++t) {
      if (route.places.empty() || route.places.back() != cells[r][t]) {
        route.places.push_back(cells[r][t]);
        route.entry_steps.push_back(static_cast<int>(t));
      }
    }
  }
  graph_.load(routes);
}

GridAction LifelongGridRun::turn_towards(int robot, int heading) const {
  const int d = (heading - robots_[robot].heading + kHeadings) % kHeadings;
  if (d == 0) return GridAction::kWait;
  return d == 3 ? GridAction::kCounterClockwise : GridAction::kClockwise;
}

GridAction LifelongGridRun::best_turn_in_place(int robot) {
  // Waiting anyway: face the way that leaves the fewest actions to the goal.
  const GridRobot& r = robots_[robot];
  const int here = distances_.to(r.goal, r.cell, r.heading);
  const int right = distances_.to(r.goal, r.cell, clockwise(r.heading));
  const int left = distances_.to(r.goal, r.cell, counter_clockwise(r.heading));
  if (right < here && right <= left) return GridAction::kClockwise;
  if (left < here) return GridAction::kCounterClockwise;
  return GridAction::kWait;
}

std::vector<bool> LifelongGridRun::draw_delays() {
  std::vector<bool> stalled(robots_.size(), false);
  const DelayModel& model = settings_.delays;
  if (model.probability <= 0.0) return stalled;
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  std::uniform_int_distribution<int> length(model.min_steps, model.max_steps);
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    if (delay_left_[r] == 0 && chance(delay_rng_) < model.probability) delay_left_[r] = length(delay_rng_);
    if (delay_left_[r] > 0) {
      stalled[r] = true;
      --delay_left_[r];
      ++result_.delayed_robot_steps;
    }
  }
  return stalled;
}

std::vector<GridAction> LifelongGridRun::decide_actions(const std::vector<bool>& stalled) {
  const int n = static_cast<int>(robots_.size());
  std::vector<GridAction> actions(n, GridAction::kWait);
  std::vector<int> ready;  // robots facing their next cell, free to go once the graph lets them
  for (int r = 0; r < n; ++r) {
    if (stalled[r]) continue;
    const int next = graph_.next_place(r);
    if (next < 0) {
      actions[r] = best_turn_in_place(r);
      continue;
    }
    const int heading = instance_.map.heading_between(robots_[r].cell, next);
    if (heading != robots_[r].heading) {
      actions[r] = turn_towards(r, heading);
    } else {
      ready.push_back(r);
    }
  }
  // Robots enter in the graph's order: one whose visit comes first goes; a follower goes once the
  // one ahead has left, in the same step. A robot left in `ready` waits for one that stays.
  for (bool moved = true; moved;) {
    moved = false;
    for (auto& r : ready) {
      if (r < 0 || graph_.waits_for(r) >= 0) continue;
      graph_.advance(r);
      actions[r] = GridAction::kForward;
      r = -1;
      moved = true;
    }
  }
  return actions;
}

void LifelongGridRun::apply(const std::vector<GridAction>& actions, const std::vector<int>& before) {
  const GridMap& map = instance_.map;
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    GridRobot& robot = robots_[r];
    switch (actions[r]) {
      case GridAction::kForward:
        robot.cell = map.step(robot.cell, robot.heading);
        break;
      case GridAction::kClockwise:
        robot.heading = clockwise(robot.heading);
        break;
      case GridAction::kCounterClockwise:
        robot.heading = counter_clockwise(robot.heading);
        break;
      case GridAction::kWait:
        break;
    }
    result_.actions[r].push_back(static_cast<char>(actions[r]));
  }
  // The competition's own rules, checked on every step: on the map, one robot a cell, no swaps.
  std::vector<int> at(static_cast<std::size_t>(map.cells()), -1);
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    const int cell = robots_[r].cell;
    if (cell < 0) {
      result_.errors.push_back("robot " + std::to_string(r) + " drove off the map or into a wall at step " +
                               std::to_string(step_));
      robots_[r].cell = before[r];
      continue;
    }
    if (at[cell] >= 0) {
      result_.errors.push_back("robots " + std::to_string(at[cell]) + " and " + std::to_string(r) + " both in cell " +
                               map.describe(cell) + " at step " + std::to_string(step_));
    }
    at[cell] = static_cast<int>(r);
  }
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    const int other = at[before[r]];
    if (other >= 0 && static_cast<std::size_t>(other) != r && robots_[r].cell == before[other]) {
      if (static_cast<std::size_t>(other) > r) {
        result_.errors.push_back("robots " + std::to_string(r) + " and " + std::to_string(other) +
                                 " swapped cells at step " + std::to_string(step_));
      }
    }
  }
}

bool LifelongGridRun::step() {
  if (step_ >= settings_.steps) return false;
  for (std::size_t r = 0; r < robots_.size(); ++r) robots_[r].held = held_last_step_[r];
  const std::vector<bool> stalled = draw_delays();
  held_last_step_ = stalled;
  const auto start = std::chrono::steady_clock::now();
  update_guide_paths();
  plan_and_load();
  std::vector<GridAction> actions = decide_actions(stalled);
  result_.planning_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  if (!graph_.wait_cycle().empty()) ++result_.wait_cycles;
  std::vector<int> before(robots_.size());
  for (std::size_t r = 0; r < robots_.size(); ++r) before[r] = robots_[r].cell;
  ++step_;
  apply(actions, before);
  for (std::size_t r = 0; r < robots_.size(); ++r) {
    still_for_[r] = robots_[r].cell == before[r] ? still_for_[r] + 1 : 0;
    result_.longest_standstill = std::max(result_.longest_standstill, still_for_[r]);
    if (robots_[r].cell == assigned_[r].front().cell) {
      result_.events[r].push_back({assigned_[r].front().id, step_, true});
      assigned_[r].erase(assigned_[r].begin());
      ++result_.finished;
      if (settings_.planner == GridPlanner::kCells) {
        cell_planner_.reached_goal(static_cast<int>(r));
      } else {
        operation_planner_.reached_goal(static_cast<int>(r));
      }
    }
  }
  hand_out_errands();
  result_.steps = step_;
  return true;
}

LifelongFigures figures_of(const LifelongResult& result) {
  LifelongFigures f;
  if (result.steps > 0) f.throughput = static_cast<double>(result.finished) / result.steps;
  std::vector<double> ms;
  for (double s : result.planning_s) ms.push_back(s * 1e3);
  if (ms.empty()) return f;
  f.planning_ms_p50 = common::percentile(ms, 0.5);
  f.planning_ms_p99 = common::percentile(ms, 0.99);
  f.planning_ms_max = *std::max_element(ms.begin(), ms.end());
  return f;
}

const LifelongResult& LifelongGridRun::run() {
  while (step()) {
  }
  return result_;
}

}  // namespace fleet::coordination
