#include "coordination/grid_operation_pibt.hpp"

#include <algorithm>
#include <numeric>
#include <set>
#include <tuple>

namespace fleet::coordination {

namespace {

constexpr int kFarAway = 1 << 20;
/// Priority added for a robot in a dead end: it can make room only by leaving.
constexpr double kDeadEndBoost = 10.0;
/// Steps a robot with an errand may stand before standing costs more the longer it stands.
constexpr int kStillBeforeMovingOn = 4;
/// Pushes a plan step may make, per robot.
constexpr std::size_t kPushesPerRobot = 64;
constexpr char kActions[] = {'F', 'R', 'C', 'W'};

int turns_in(const std::string& operation) {
  return static_cast<int>(
      std::count_if(operation.begin(), operation.end(), [](char a) { return a == 'R' || a == 'C'; }));
}

}  // namespace

std::vector<std::string> GridOperationPibt::operations(int depth) {
  std::vector<std::string> all{""};
  for (int d = 0; d < depth; ++d) {
    std::vector<std::string> longer;
    for (const std::string& prefix : all) {
      for (const char a : kActions) longer.push_back(prefix + a);
    }
    all = std::move(longer);
  }
  // Fewest quarter turns first, so of operations with one effect the one kept turns least.
  std::stable_sort(all.begin(), all.end(),
                   [](const std::string& a, const std::string& b) { return turns_in(a) < turns_in(b); });
  // The effect on an open plane, from (0, 0) facing east: the cells of every step, the last heading.
  std::set<std::vector<int>> seen;
  std::vector<std::string> kept;
  for (const std::string& operation : all) {
    std::vector<int> effect;
    int x = 0;
    int y = 0;
    int heading = 0;
    for (const char a : operation) {
      if (a == 'F') {
        constexpr int kDx[] = {1, 0, -1, 0};
        constexpr int kDy[] = {0, 1, 0, -1};
        x += kDx[heading];
        y += kDy[heading];
      } else if (a == 'R') {
        heading = clockwise(heading);
      } else if (a == 'C') {
        heading = counter_clockwise(heading);
      }
      effect.push_back(x);
      effect.push_back(y);
    }
    effect.push_back(heading);
    if (seen.insert(effect).second) kept.push_back(operation);
  }
  return kept;
}

GridOperationPibt::GridOperationPibt(const GridMap& map, HeadingDistances& distances, std::uint64_t seed)
    : map_(map),
      distances_(distances),
      rng_(seed),
      cells_(static_cast<std::size_t>(map.cells())),
      standing_(static_cast<std::size_t>(map.cells()), -1) {}

void GridOperationPibt::reached_goal(int robot) {
  if (robot < static_cast<int>(priority_.size())) {
    priority_[static_cast<std::size_t>(robot)] = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
  }
}

int GridOperationPibt::actions_left(int robot, int cell, int heading) {
  return actions_to_goal(guides_, distances_, robot, robots_[static_cast<std::size_t>(robot)].goal, cell, heading);
}

std::vector<int> GridOperationPibt::planned_headings(int robot) const {
  Trace t;
  trace(robots_[static_cast<std::size_t>(robot)], last_[static_cast<std::size_t>(robot)], t);
  return t.headings;
}

bool GridOperationPibt::trace(const GridRobot& robot, const std::string& operation, Trace& out) const {
  out.cells.assign(1, robot.cell);
  out.headings.assign(1, robot.heading);
  int cell = robot.cell;
  int heading = robot.heading;
  for (const char a : operation) {
    if (a == 'F') {
      cell = map_.step(cell, heading);
      if (cell < 0) return false;
    } else if (a == 'R') {
      heading = clockwise(heading);
    } else if (a == 'C') {
      heading = counter_clockwise(heading);
    }
    out.cells.push_back(cell);
    out.headings.push_back(heading);
  }
  return true;
}

bool GridOperationPibt::closes_ring(int robot, const Trace& t, int step) const {
  // Follow the planned robots that leave, at this step, the cell the robot enters: meeting the
  // robot's own cell again is a ring, each waiting for the one ahead to leave.
  const int from = t.cells[static_cast<std::size_t>(step - 1)];
  int cell = t.cells[static_cast<std::size_t>(step)];
  for (std::size_t guard = 0; guard <= robots_.size(); ++guard) {
    const int other = holder(step - 1, cell);
    if (other < 0 || other == robot) return false;
    const int onward = path_[static_cast<std::size_t>(other)][static_cast<std::size_t>(step)];
    if (onward == cell) return false;
    if (onward == from) return true;
    cell = onward;
  }
  return false;
}

bool GridOperationPibt::admissible(int robot, const Trace& t, std::vector<int>& pushed,
                                   std::vector<int>& entry_steps) const {
  pushed.clear();
  entry_steps.clear();
  for (int step = 1; step <= depth_; ++step) {
    const int cell = t.cells[static_cast<std::size_t>(step)];
    const int there = holder(step, cell);
    if (there >= 0 && there != robot) return false;
    const int before = t.cells[static_cast<std::size_t>(step - 1)];
    if (cell != before) {
      const int leaving = holder(step - 1, cell);
      if (leaving >= 0 && leaving != robot && holder(step, before) == leaving) return false;  // a swap
      if (closes_ring(robot, t, step)) return false;
    }
    const int standing = standing_[static_cast<std::size_t>(cell)];
    if (standing < 0 || standing == robot) continue;
    // A robot still planning may fall back to standing where it is.
    if (planning_[static_cast<std::size_t>(standing)]) return false;
    if (path_[static_cast<std::size_t>(standing)].empty() &&
        std::find(pushed.begin(), pushed.end(), standing) == pushed.end()) {
      pushed.push_back(standing);
      entry_steps.push_back(step);
    }
  }
  return true;
}

void GridOperationPibt::reserve(int robot, const Trace& t) {
  path_[static_cast<std::size_t>(robot)] = t.cells;
  for (int step = 0; step <= depth_; ++step) {
    held_[static_cast<std::size_t>(step) * cells_ + static_cast<std::size_t>(t.cells[static_cast<std::size_t>(step)])] =
        robot;
  }
}

void GridOperationPibt::release(int robot) {
  auto& path = path_[static_cast<std::size_t>(robot)];
  for (int step = 0; step <= depth_ && step < static_cast<int>(path.size()); ++step) {
    int& h =
        held_[static_cast<std::size_t>(step) * cells_ + static_cast<std::size_t>(path[static_cast<std::size_t>(step)])];
    if (h == robot) h = -1;
  }
  path.clear();
}

void GridOperationPibt::stay(int robot) {
  Trace t;
  t.cells.assign(static_cast<std::size_t>(depth_) + 1, robots_[static_cast<std::size_t>(robot)].cell);
  reserve(robot, t);
  chosen_[static_cast<std::size_t>(robot)] = std::string(static_cast<std::size_t>(depth_), 'W');
}

bool GridOperationPibt::plan_robot(int robot, int leave_by) {
  const auto self = static_cast<std::size_t>(robot);
  // A robot pushed and failing stays unplanned, so it may be pushed again by the pusher's next
  // operation, given longer to leave: one that could not leave by a step is not asked again to
  // leave as early, and a budget of pushes a plan step bounds the rest.
  if (leave_by > 0) {
    if (leave_by <= cannot_leave_by_[self] || pushes_left_-- <= 0) return false;
  }
  const GridRobot& r = robots_[self];
  struct Candidate {
    std::size_t operation;
    int cost;
    int progress;
    int pushes;
    int fresh;  ///< 0 when it goes on with the robot's last operation
    unsigned tie;
  };
  std::vector<Candidate> candidates;
  std::vector<Trace> traces;
  std::vector<int> pushed;
  std::vector<int> entry_steps;
  const std::string& last = last_[self];
  for (std::size_t k = 0; k < operations_.size(); ++k) {
    Trace t;
    if (!trace(r, operations_[k], t)) continue;
    Candidate c{k, 0, 0, 0, 1, static_cast<unsigned>(rng_())};
    if (r.goal < 0) {
      c.progress = depth_ - static_cast<int>(std::count(operations_[k].begin(), operations_[k].end(), 'W'));
    } else {
      c.cost = -1;
      for (int step = 1; step <= depth_ && c.cost < 0; ++step) {
        const auto s = static_cast<std::size_t>(step);
        if (t.cells[s] == r.goal) {
          c.cost = step;
          break;
        }
        const int left = actions_left(robot, t.cells[s], t.headings[s]);
        c.progress += left >= HeadingDistances::kUnreachable ? kFarAway : left;
      }
      if (c.cost < 0) {
        const int left = actions_left(robot, t.cells.back(), t.headings.back());
        c.cost = left >= HeadingDistances::kUnreachable ? kFarAway : depth_ + left;
        // A robot that has stood long pays for standing on: two robots that want each other's
        // cells and cannot push each other out stand for good unless one goes round.
        if (t.cells.back() == r.cell) c.cost += std::max(0, still_[self] - kStillBeforeMovingOn);
      }
    }
    for (int step = 1; step <= depth_; ++step) {
      const int standing = standing_[static_cast<std::size_t>(t.cells[static_cast<std::size_t>(step)])];
      if (standing >= 0 && standing != robot) ++c.pushes;
    }
    if (!last.empty() && operations_[k].compare(0, last.size() - 1, last, 1) == 0) c.fresh = 0;
    candidates.push_back(c);
    traces.push_back(std::move(t));
  }
  std::vector<std::size_t> order(candidates.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    const Candidate& x = candidates[a];
    const Candidate& y = candidates[b];
    return std::tie(x.cost, x.progress, x.pushes, x.fresh, x.tie) <
           std::tie(y.cost, y.progress, y.pushes, y.fresh, y.tie);
  });
  planning_[self] = 1;
  for (const std::size_t i : order) {
    const Trace& t = traces[i];
    if (!admissible(robot, t, pushed, entry_steps)) continue;
    reserve(robot, t);
    bool cleared = true;
    for (std::size_t k = 0; k < pushed.size(); ++k) {
      const int other = pushed[k];
      if (!path_[static_cast<std::size_t>(other)].empty()) continue;  // planned meanwhile, clear of this one
      if (!plan_robot(other, entry_steps[k])) {
        cannot_leave_by_[static_cast<std::size_t>(other)] =
            std::max(cannot_leave_by_[static_cast<std::size_t>(other)], entry_steps[k]);
        // It cannot get out in time: this robot tries its next operation, which may give it
        // longer (entering later) or go round it. It stays unplanned, standing where it is.
        release(robot);
        cleared = false;
        break;
      }
    }
    if (cleared) {
      chosen_[self] = operations_[candidates[i].operation];
      planning_[self] = 0;
      return true;
    }
  }
  planning_[self] = 0;
  return false;
}

std::vector<std::vector<int>> GridOperationPibt::plan(const std::vector<GridRobot>& robots, int depth) {
  const std::size_t n = robots.size();
  if (depth != depth_) {
    depth_ = depth;
    operations_ = operations(depth);
    last_.assign(n, "");
  }
  if (priority_.size() != n) {
    priority_.resize(n);
    for (auto& p : priority_) p = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
    last_.assign(n, "");
  }
  if (last_cell_.size() != n) {
    last_cell_.assign(n, -1);
    still_.assign(n, 0);
  }
  for (std::size_t i = 0; i < n; ++i) {
    still_[i] = robots[i].cell == last_cell_[i] && robots[i].goal >= 0 ? still_[i] + 1 : 0;
    last_cell_[i] = robots[i].cell;
  }
  robots_ = robots;
  held_.assign((static_cast<std::size_t>(depth_) + 1) * cells_, -1);
  std::fill(standing_.begin(), standing_.end(), -1);
  for (std::size_t i = 0; i < n; ++i) standing_[static_cast<std::size_t>(robots[i].cell)] = static_cast<int>(i);
  path_.assign(n, {});
  planning_.assign(n, 0);
  chosen_.assign(n, "");
  pushes_left_ = static_cast<long>(kPushesPerRobot * n);
  cannot_leave_by_.assign(n, 0);
  // A held robot stays: the others plan round it rather than queue behind it or push it.
  for (std::size_t i = 0; i < n; ++i) {
    if (robots[i].held) stay(static_cast<int>(i));
  }
  std::vector<double> rank(n);
  for (std::size_t i = 0; i < n; ++i) {
    int exits = 0;
    for (int h = 0; h < kHeadings; ++h) exits += map_.step(robots[i].cell, h) >= 0 ? 1 : 0;
    rank[i] = priority_[i] + (exits == 1 && robots[i].goal >= 0 ? kDeadEndBoost : 0.0);
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return rank[a] > rank[b]; });
  for (const int robot : order) {
    // Standing is always free for a robot nobody has pushed, so this plans it.
    if (path_[static_cast<std::size_t>(robot)].empty() && !plan_robot(robot, 0)) stay(robot);
  }
  for (std::size_t i = 0; i < n; ++i) priority_[i] += 1.0;
  last_ = chosen_;
  return path_;
}

}  // namespace fleet::coordination
