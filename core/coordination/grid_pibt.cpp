#include "coordination/grid_pibt.hpp"

#include <algorithm>
#include <array>
#include <numeric>

namespace fleet::coordination {

namespace {

constexpr int kFarAway = 1 << 20;
/// Steps a robot keeps a chosen cell it has not reached: two quarter turns and the move in.
constexpr int kCommitSteps = 3;
/// Priority added for a robot in a dead end: it can make room only by leaving.
constexpr double kDeadEndBoost = 10.0;

}  // namespace

GridPibt::GridPibt(const GridMap& map, HeadingDistances& distances, std::uint64_t seed)
    : map_(map),
      distances_(distances),
      rng_(seed),
      now_(static_cast<std::size_t>(map.cells()), -1),
      next_(static_cast<std::size_t>(map.cells()), -1) {}

void GridPibt::reached_goal(int robot) {
  if (robot < static_cast<int>(priority_.size())) {
    priority_[robot] = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
  }
}

int GridPibt::candidate_cost(int robot, int cell, int heading) const {
  const GridRobot& r = robots_[robot];
  if (r.goal < 0) return 0;
  if (cell == r.cell) {
    // Waiting one step, turned the best way meanwhile.
    int best = distances_.to(r.goal, r.cell, r.heading);
    best = std::min(best, distances_.to(r.goal, r.cell, clockwise(r.heading)));
    best = std::min(best, distances_.to(r.goal, r.cell, counter_clockwise(r.heading)));
    return best >= HeadingDistances::kUnreachable ? kFarAway : 1 + best;
  }
  const int rest = distances_.to(r.goal, cell, heading);
  return rest >= HeadingDistances::kUnreachable ? kFarAway : quarter_turns(r.heading, heading) + 1 + rest;
}

bool GridPibt::closes_cycle(int robot, int cell) const {
  // Follow the robots that move out of one another's way from `cell` on; meeting `robot` again
  // means a ring of robots that would each wait for the one ahead.
  for (int steps = 0, c = cell; steps <= static_cast<int>(robots_.size()); ++steps) {
    const int standing = now_[c];
    if (standing < 0) return false;
    if (standing == robot) return true;
    const int onward = planned_[standing];
    if (onward < 0 || onward == c) return false;
    c = onward;
  }
  return false;
}

bool GridPibt::plan_robot(int robot, int pusher) {
  const GridRobot& r = robots_[robot];
  struct Candidate {
    int cell, cost, turns, occupied;
    unsigned tie;
  };
  std::array<Candidate, 5> candidates{};
  int count = 0;
  auto add = [&](int cell) {
    const int heading = cell == r.cell ? r.heading : map_.heading_between(r.cell, cell);
    candidates[count++] = {cell, candidate_cost(robot, cell, heading), quarter_turns(r.heading, heading),
                           now_[cell] >= 0 && now_[cell] != robot ? 1 : 0, static_cast<unsigned>(rng_())};
  };
  add(r.cell);
  for (int h = 0; h < kHeadings; ++h) {
    if (const int cell = map_.step(r.cell, h); cell >= 0) add(cell);
  }
  // A robot pushed out takes first a cell it faces: one it must turn to first keeps it where it is
  // this step, and turning one way one step and another the next would keep it there for good.
  const bool pushed = pusher >= 0;
  auto before = [pushed](const Candidate& a, const Candidate& b) {
    if (pushed && (a.turns == 0) != (b.turns == 0)) return a.turns == 0;
    if (a.cost != b.cost) return a.cost < b.cost;
    if (a.turns != b.turns) return a.turns < b.turns;
    if (a.occupied != b.occupied) return a.occupied < b.occupied;
    return a.tie < b.tie;
  };
  // Five candidates at most: an insertion sort.
  for (int i = 1; i < count; ++i) {
    for (int j = i; j > 0 && before(candidates[j], candidates[j - 1]); --j) std::swap(candidates[j], candidates[j - 1]);
  }
  // Waiting comes last once the best cell is held by a robot that cannot move out: stepping
  // aside is how a robot in a dead end gets out past one that wants its cell.
  bool best_held = false;
  for (int i = 0; i < count; ++i) {
    const int cell = candidates[i].cell;
    if (cell == r.cell && best_held) continue;
    if (next_[cell] >= 0) continue;
    if (pusher >= 0 && cell == robots_[pusher].cell) continue;  // no swap with the robot pushing
    if (cell != r.cell && closes_cycle(robot, cell)) continue;
    next_[cell] = robot;
    planned_[robot] = cell;
    const int standing = now_[cell];
    if (standing < 0 || standing == robot) return true;
    if (planned_[standing] >= 0) return true;  // it moves away (no swap: it was not pushed by us)
    if (plan_robot(standing, robot)) return true;
    // The pushed robot stays: it took its own cell back, so this one tries its next candidate.
    if (i == 0) best_held = true;
  }
  if (best_held && next_[r.cell] < 0) {
    next_[r.cell] = robot;
    planned_[robot] = r.cell;
    return true;
  }
  planned_[robot] = r.cell;
  next_[r.cell] = robot;
  return false;
}

void GridPibt::plan_one_step(bool keep_commitments) {
  std::fill(now_.begin(), now_.end(), -1);
  std::fill(next_.begin(), next_.end(), -1);
  planned_.assign(robots_.size(), -1);
  for (std::size_t i = 0; i < robots_.size(); ++i) now_[robots_[i].cell] = static_cast<int>(i);
  // A held robot stays: the others plan round it rather than queue behind it or push it.
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    if (robots_[i].held) {
      planned_[i] = robots_[i].cell;
      next_[robots_[i].cell] = static_cast<int>(i);
    }
  }
  order_.resize(robots_.size());
  std::iota(order_.begin(), order_.end(), 0);
  auto rank = [&](int r) {
    int exits = 0;
    for (int h = 0; h < kHeadings; ++h) exits += map_.step(robots_[r].cell, h) >= 0 ? 1 : 0;
    return priority_[r] + (exits == 1 && robots_[r].goal >= 0 ? kDeadEndBoost : 0.0);
  };
  std::vector<double> ranks(robots_.size());
  for (std::size_t i = 0; i < robots_.size(); ++i) ranks[i] = rank(static_cast<int>(i));
  std::stable_sort(order_.begin(), order_.end(), [&](int a, int b) { return ranks[a] > ranks[b]; });
  // Robots that keep a chosen cell go first: each lends its priority to the robot standing there,
  // and plans afresh below when that one cannot move out.
  if (keep_commitments) {
    for (int robot : order_) {
      if (committed_[robot] >= 0 && planned_[robot] < 0) keep_commitment(robot, committed_[robot]);
    }
  }
  for (int robot : order_) {
    if (planned_[robot] < 0) plan_robot(robot, -1);
  }
}

void GridPibt::keep_commitment(int robot, int cell) {
  if (next_[cell] >= 0 || closes_cycle(robot, cell)) return;
  next_[cell] = robot;
  planned_[robot] = cell;
  const int standing = now_[cell];
  if (standing < 0 || planned_[standing] >= 0 || plan_robot(standing, robot)) return;
  // The robot standing there stays and has taken its cell back.
  planned_[robot] = -1;
}

void GridPibt::commit(const std::vector<GridRobot>& robots) {
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const int to = planned_[i];
    if (to == robots[i].cell) {
      committed_[i] = -1;
    } else if (to == committed_[i]) {
      if (++committed_for_[i] >= kCommitSteps) committed_[i] = -1;
    } else {
      const int heading = map_.heading_between(robots[i].cell, to);
      committed_[i] = heading == robots[i].heading ? -1 : to;
      committed_for_[i] = 0;
    }
  }
}

std::vector<std::vector<int>> GridPibt::plan(const std::vector<GridRobot>& robots, int window) {
  if (priority_.size() != robots.size()) {
    priority_.resize(robots.size());
    for (auto& p : priority_) p = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
  }
  if (committed_.size() != robots.size()) {
    committed_.assign(robots.size(), -1);
    committed_for_.assign(robots.size(), 0);
  }
  for (std::size_t i = 0; i < robots.size(); ++i) {
    if (committed_[i] == robots[i].cell || map_.heading_between(robots[i].cell, committed_[i]) < 0) committed_[i] = -1;
  }
  robots_ = robots;
  std::vector<std::vector<int>> cells(robots.size());
  for (std::size_t i = 0; i < robots.size(); ++i) cells[i].push_back(robots[i].cell);
  for (int step = 0; step < window; ++step) {
    plan_one_step(step == 0);
    if (step == 0) commit(robots);
    for (std::size_t i = 0; i < robots_.size(); ++i) {
      GridRobot& r = robots_[i];
      const int to = planned_[i];
      if (to != r.cell) r.heading = map_.heading_between(r.cell, to);
      r.cell = to;
      cells[i].push_back(to);
    }
  }
  for (std::size_t i = 0; i < robots.size(); ++i) priority_[i] += 1.0;
  return cells;
}

}  // namespace fleet::coordination
