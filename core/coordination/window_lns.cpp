#include "coordination/window_lns.hpp"

#include <algorithm>
#include <numeric>
#include <queue>
#include <string>
#include <tuple>

namespace fleet::coordination {

namespace {

constexpr int kFarAway = 1 << 20;
/// States a search may take from its queue before it gives up: bounds a search that finds no
/// path in a crowded window.
constexpr int kExpansionsPerSearch = 20000;
/// Steps a robot with an errand may stand in one cell before a window in which it stands on costs
/// it one more for each further step: a robot shut in by others whose goals it holds is let out.
constexpr int kStoodBeforeMovingOn = 8;
/// Robots drawn to find one whose path costs more than it would alone.
constexpr int kDrawsForALateRobot = 8;
/// Actions walked down a late robot's way to its goal to find the robots on it: four windows'
/// worth, for the robots standing further on hold it up in the windows to come.
constexpr int kActionsWalked = 24;

}  // namespace

WindowLns::WindowLns(const GridMap& map, HeadingDistances& distances, std::uint64_t seed)
    : map_(map), distances_(distances), rng_(seed), cells_(static_cast<std::size_t>(map.cells())) {}

int WindowLns::actions_left(int robot, int cell, int heading) {
  const int goal = robots_[static_cast<std::size_t>(robot)].goal;
  const int left = actions_to_goal(guides_, distances_, robot, goal, cell, heading);
  return left >= HeadingDistances::kUnreachable ? kFarAway : left;
}

int WindowLns::path_cost(int robot, const WindowPath& path) {
  const int goal = robots_[static_cast<std::size_t>(robot)].goal;
  if (goal < 0) return 0;
  for (int t = 0; t <= horizon_; ++t) {
    if (path.cells[static_cast<std::size_t>(t)] == goal) return t;
  }
  return horizon_ + actions_left(robot, path.cells.back(), path.headings.back()) +
         standing_penalty(robot, path.cells.back());
}

int WindowLns::standing_penalty(int robot, int end_cell) const {
  const auto r = static_cast<std::size_t>(robot);
  if (r >= stood_.size() || end_cell != robots_[r].cell || robots_[r].goal < 0) return 0;
  return std::max(0, stood_[r] - kStoodBeforeMovingOn);
}

long WindowLns::cost(const std::vector<GridRobot>& robots, const std::vector<WindowPath>& plan) {
  robots_ = robots;
  horizon_ = plan.empty() ? 0 : static_cast<int>(plan.front().cells.size()) - 1;
  long sum = 0;
  for (std::size_t r = 0; r < plan.size(); ++r) sum += path_cost(static_cast<int>(r), plan[r]);
  return sum;
}

void WindowLns::occupy(int robot, const WindowPath& path) {
  for (int t = 0; t <= horizon_; ++t) {
    occupied_[static_cast<std::size_t>(t) * cells_ +
              static_cast<std::size_t>(path.cells[static_cast<std::size_t>(t)])] = robot;
  }
}

void WindowLns::vacate(int robot, const WindowPath& path) {
  for (int t = 0; t <= horizon_; ++t) {
    int& holder = occupied_[static_cast<std::size_t>(t) * cells_ +
                            static_cast<std::size_t>(path.cells[static_cast<std::size_t>(t)])];
    if (holder == robot) holder = -1;
  }
}

bool WindowLns::closes_ring(int robot, int from, int to, int step) const {
  // Follow the robots that leave, at `step`, the cell the one before them enters: coming back to
  // `from` closes a ring of robots each waiting for the next to leave.
  int cell = to;
  for (std::size_t guard = 0; guard <= robots_.size(); ++guard) {
    const int other = at(step - 1, cell);
    if (other < 0 || other == robot) return false;
    const int onward = (*plan_)[static_cast<std::size_t>(other)].cells[static_cast<std::size_t>(step)];
    if (onward == cell) return false;
    if (onward == from) return true;
    cell = onward;
  }
  return false;
}

bool WindowLns::search(int robot, WindowPath& out) {
  const GridRobot& r = robots_[static_cast<std::size_t>(robot)];
  const std::size_t states = (static_cast<std::size_t>(horizon_) + 1) * cells_ * kHeadings;
  if (best_g_.size() != states) {
    best_g_.assign(states, 0);
    parent_.assign(states, -1);
    seen_.assign(states, 0);
    stamp_ = 0;
  }
  if (++stamp_ == 0) {
    std::fill(seen_.begin(), seen_.end(), 0);
    stamp_ = 1;
  }
  const auto index = [&](int t, int cell, int heading) {
    return (static_cast<std::size_t>(t) * cells_ + static_cast<std::size_t>(cell)) * kHeadings +
           static_cast<std::size_t>(heading);
  };
  const bool has_goal = r.goal >= 0;
  // Open states by (f, -t): of equal cost the deeper first, so a robot without a goal, whose
  // every path costs nothing, is done in one dive.
  using Entry = std::tuple<int, int, int>;  // f, -t, state
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const auto push = [&](int t, int cell, int heading, int g, int from) {
    const std::size_t s = index(t, cell, heading);
    if (seen_[s] == stamp_ && best_g_[s] <= g) return;
    seen_[s] = stamp_;
    best_g_[s] = g;
    parent_[s] = from;
    const int h = has_goal ? actions_left(robot, cell, heading) : 0;
    open.emplace(g + h + (t == horizon_ ? standing_penalty(robot, cell) : 0), -t, static_cast<int>(s));
  };
  push(0, r.cell, r.heading, 0, -1);
  int found = -1;
  for (int expansions = 0; !open.empty() && expansions < kExpansionsPerSearch; ++expansions) {
    const auto [f, minus_t, state] = open.top();
    open.pop();
    const int t = -minus_t;
    const int cell = state / kHeadings % static_cast<int>(cells_);
    const int heading = state % kHeadings;
    const int g = best_g_[static_cast<std::size_t>(state)];
    if (f > g + (has_goal ? actions_left(robot, cell, heading) : 0) && t < horizon_) continue;  // stale
    if (t == horizon_) {
      found = state;
      break;
    }
    if (has_goal && cell == r.goal) {
      // At the goal: done when it may stand there to the window's end.
      bool free = true;
      for (int k = t + 1; k <= horizon_ && free; ++k) free = at(k, cell) < 0 || at(k, cell) == robot;
      if (free) {
        found = state;
        break;
      }
    }
    const int next_g = has_goal ? g + 1 : 0;
    // Standing or turning: the cell must stay free at the next step.
    if (at(t + 1, cell) < 0 || at(t + 1, cell) == robot) {
      push(t + 1, cell, heading, next_g, state);
      push(t + 1, cell, clockwise(heading), next_g, state);
      push(t + 1, cell, counter_clockwise(heading), next_g, state);
    }
    const int ahead = map_.step(cell, heading);
    if (ahead < 0) continue;
    const int there = at(t + 1, ahead);
    if (there >= 0 && there != robot) continue;
    const int leaving = at(t, ahead);
    if (leaving >= 0 && leaving != robot && at(t + 1, cell) == leaving) continue;  // a swap
    if (closes_ring(robot, cell, ahead, t + 1)) continue;
    push(t + 1, ahead, heading, next_g, state);
  }
  if (found < 0) return false;
  // Walk back from the state found; a path that ends early at the goal stands there to the end.
  std::vector<int> chain;
  for (int s = found; s >= 0; s = parent_[static_cast<std::size_t>(s)]) chain.push_back(s);
  std::reverse(chain.begin(), chain.end());
  out.cells.clear();
  out.headings.clear();
  for (const int s : chain) {
    out.cells.push_back(s / kHeadings % static_cast<int>(cells_));
    out.headings.push_back(s % kHeadings);
  }
  while (static_cast<int>(out.cells.size()) <= horizon_) {
    out.cells.push_back(out.cells.back());
    out.headings.push_back(out.headings.back());
  }
  return true;
}

int WindowLns::draw_late_robot(const std::vector<int>& movable, const std::vector<int>& costs,
                               const std::vector<int>& least) {
  // Of a few drawn, the first whose path costs more than it would alone: others hold it up.
  int robot = movable[rng_() % movable.size()];
  for (int draw = 1;
       draw < kDrawsForALateRobot && costs[static_cast<std::size_t>(robot)] <= least[static_cast<std::size_t>(robot)];
       ++draw) {
    robot = movable[rng_() % movable.size()];
  }
  return robot;
}

void WindowLns::add_passing(int cell, std::vector<int>& group, int size) {
  for (int t = 0; t <= horizon_ && static_cast<int>(group.size()) < size; ++t) {
    const int robot = at(t, cell);
    if (robot < 0 || in_group_[static_cast<std::size_t>(robot)] == reach_stamp_ ||
        robots_[static_cast<std::size_t>(robot)].held) {
      continue;
    }
    in_group_[static_cast<std::size_t>(robot)] = reach_stamp_;
    group.push_back(robot);
  }
}

std::vector<int> WindowLns::neighbourhood(int seed_robot, int size) {
  if (reached_.size() != cells_) reached_.assign(cells_, 0);
  if (in_group_.size() != robots_.size()) in_group_.assign(robots_.size(), 0);
  if (++reach_stamp_ == 0) {
    std::fill(reached_.begin(), reached_.end(), 0);
    std::fill(in_group_.begin(), in_group_.end(), 0);
    reach_stamp_ = 1;
  }
  // Down the seed's way to its goal, action by action (ties drawn at random), the robots whose
  // paths pass the cells it would drive through [Li 2021b, section 4].
  std::vector<int> group{seed_robot};
  in_group_[static_cast<std::size_t>(seed_robot)] = reach_stamp_;
  const GridRobot& seed = robots_[static_cast<std::size_t>(seed_robot)];
  int cell = seed.cell;
  int heading = seed.heading;
  int left = actions_left(seed_robot, cell, heading);
  for (int walked = 0; walked < kActionsWalked && left > 0 && left < kFarAway && static_cast<int>(group.size()) < size;
       ++walked) {
    const std::pair<int, int> options[] = {
        {map_.step(cell, heading), heading}, {cell, clockwise(heading)}, {cell, counter_clockwise(heading)}};
    int chosen = -1;
    int ties = 0;
    for (int k = 0; k < 3; ++k) {
      if (options[k].first < 0 || actions_left(seed_robot, options[k].first, options[k].second) != left - 1) continue;
      if (rng_() % static_cast<unsigned>(++ties) == 0) chosen = k;
    }
    if (chosen < 0) break;
    cell = options[chosen].first;
    heading = options[chosen].second;
    --left;
    if (reached_[static_cast<std::size_t>(cell)] == reach_stamp_) continue;
    reached_[static_cast<std::size_t>(cell)] = reach_stamp_;
    add_passing(cell, group, size);
  }
  return group;
}

long WindowLns::improve(const std::vector<GridRobot>& robots, std::vector<WindowPath>& plan, int neighbourhoods,
                        int size) {
  robots_ = robots;
  plan_ = &plan;
  horizon_ = plan.empty() ? 0 : static_cast<int>(plan.front().cells.size()) - 1;
  occupied_.assign((static_cast<std::size_t>(horizon_) + 1) * cells_, -1);
  std::vector<int> costs(plan.size());
  std::vector<int> least(plan.size(), 0);  ///< per robot: its cost alone on the map
  std::vector<int> movable;
  for (std::size_t r = 0; r < plan.size(); ++r) {
    occupy(static_cast<int>(r), plan[r]);
    costs[r] = path_cost(static_cast<int>(r), plan[r]);
    if (robots[r].goal >= 0 && !robots[r].held) {
      movable.push_back(static_cast<int>(r));
      least[r] = actions_left(static_cast<int>(r), robots[r].cell, robots[r].heading);
    }
  }
  long total = std::accumulate(costs.begin(), costs.end(), 0L);
  if (movable.empty()) return total;
  std::vector<WindowPath> kept;
  for (int round = 0; round < neighbourhoods; ++round) {
    std::vector<int> group = neighbourhood(draw_late_robot(movable, costs, least), size);
    std::shuffle(group.begin(), group.end(), rng_);
    long before = 0;
    kept.clear();
    for (const int r : group) {
      before += costs[static_cast<std::size_t>(r)];
      kept.push_back(plan[static_cast<std::size_t>(r)]);
      vacate(r, plan[static_cast<std::size_t>(r)]);
    }
    long after = 0;
    std::size_t searched = 0;
    for (; searched < group.size(); ++searched) {
      const int r = group[searched];
      WindowPath path;
      if (!search(r, path)) break;
      plan[static_cast<std::size_t>(r)] = std::move(path);
      occupy(r, plan[static_cast<std::size_t>(r)]);
      after += path_cost(r, plan[static_cast<std::size_t>(r)]);
      if (after >= before) {
        ++searched;
        break;
      }
    }
    if (searched == group.size() && after < before) {
      for (const int r : group) costs[static_cast<std::size_t>(r)] = path_cost(r, plan[static_cast<std::size_t>(r)]);
      total += after - before;
      continue;
    }
    // Worse or stuck: the old paths go back.
    for (std::size_t k = 0; k < searched; ++k) vacate(group[k], plan[static_cast<std::size_t>(group[k])]);
    for (std::size_t k = 0; k < group.size(); ++k) {
      plan[static_cast<std::size_t>(group[k])] = kept[k];
      occupy(group[k], kept[k]);
    }
  }
  plan_ = nullptr;
  return total;
}

bool WindowLns::valid(const GridMap& map, const std::vector<WindowPath>& plan, std::string* why) {
  const auto fail = [&](const std::string& reason) {
    if (why != nullptr) *why = reason;
    return false;
  };
  if (plan.empty()) return true;
  const std::size_t steps = plan.front().cells.size();
  std::vector<int> at(static_cast<std::size_t>(map.cells()) * steps, -1);
  for (std::size_t r = 0; r < plan.size(); ++r) {
    if (plan[r].cells.size() != steps || plan[r].headings.size() != steps) return fail("paths of unequal length");
    for (std::size_t t = 0; t < steps; ++t) {
      const int cell = plan[r].cells[t];
      if (!map.is_free(cell)) return fail("robot " + std::to_string(r) + " off the free cells");
      if (t > 0 && cell != plan[r].cells[t - 1] &&
          (map.step(plan[r].cells[t - 1], plan[r].headings[t - 1]) != cell ||
           plan[r].headings[t] != plan[r].headings[t - 1])) {
        return fail("robot " + std::to_string(r) + " moves where it does not face");
      }
      if (t > 0 && cell == plan[r].cells[t - 1] && quarter_turns(plan[r].headings[t - 1], plan[r].headings[t]) > 1) {
        return fail("robot " + std::to_string(r) + " turns twice in a step");
      }
      int& holder = at[t * static_cast<std::size_t>(map.cells()) + static_cast<std::size_t>(cell)];
      if (holder >= 0) return fail("robots share a cell");
      holder = static_cast<int>(r);
    }
  }
  for (std::size_t t = 1; t < steps; ++t) {
    for (std::size_t r = 0; r < plan.size(); ++r) {
      // Follow the robots each entering the cell the next leaves: a chain back to r is a ring.
      int cell = plan[r].cells[t];
      if (cell == plan[r].cells[t - 1]) continue;
      for (std::size_t guard = 0; guard <= plan.size(); ++guard) {
        const int other = at[(t - 1) * static_cast<std::size_t>(map.cells()) + static_cast<std::size_t>(cell)];
        if (other < 0) break;
        if (static_cast<std::size_t>(other) == r) return fail("a swap or ring of robots");
        const int onward = plan[static_cast<std::size_t>(other)].cells[t];
        if (onward == cell) break;
        cell = onward;
      }
    }
  }
  return true;
}

}  // namespace fleet::coordination
