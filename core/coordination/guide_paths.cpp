#include "coordination/guide_paths.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace fleet::coordination {

namespace {

int opposite(int heading) {
  return (heading + 2) % kHeadings;
}

}  // namespace

GuidePaths::GuidePaths(const GridMap& map, int robots)
    : map_(map),
      flow_(static_cast<std::size_t>(map.cells()) * kHeadings, 0),
      path_(static_cast<std::size_t>(robots)),
      passed_(static_cast<std::size_t>(robots), 0),
      goal_(static_cast<std::size_t>(robots), -1),
      field_(static_cast<std::size_t>(robots)) {}

int GuidePaths::move_cost(int cell, int heading) const {
  const int next = map_.step(cell, heading);
  const int along = flow(cell, heading);
  const int against = flow(next, opposite(heading));
  int crowd = 0;
  for (int h = 0; h < kHeadings; ++h) crowd += flow(next, h);
  return 1 + weights_.contraflow * (along + 1) * against + crowd * weights_.crowd_percent / 100;
}

std::vector<int> GuidePaths::search(int from, int heading, int goal) const {
  // Dijkstra over (cell, heading) with the congestion costs on the moves and one for a quarter
  // turn, so that of two ways equally free the one with fewer turns is taken; every cost is at
  // least 1, so the first time the goal is taken from the queue its path is cheapest.
  const auto states = static_cast<std::size_t>(map_.cells()) * kHeadings;
  std::vector<int> cost(states, std::numeric_limits<int>::max());
  std::vector<int> parent(states, -1);
  using Entry = std::pair<int, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const int start = from * kHeadings + heading;
  cost[static_cast<std::size_t>(start)] = 0;
  open.emplace(0, start);
  int reached = -1;
  while (!open.empty()) {
    const auto [c, state] = open.top();
    open.pop();
    if (c != cost[static_cast<std::size_t>(state)]) continue;
    const int cell = state / kHeadings;
    const int h = state % kHeadings;
    if (cell == goal) {
      reached = state;
      break;
    }
    const int next = map_.step(cell, h);
    const std::pair<int, int> successors[] = {
        {next >= 0 ? next * kHeadings + h : -1, next >= 0 ? move_cost(cell, h) : 0},
        {cell * kHeadings + clockwise(h), 1},
        {cell * kHeadings + counter_clockwise(h), 1}};
    for (const auto& [to, step_cost] : successors) {
      if (to < 0) continue;
      const int through = c + step_cost;
      if (through < cost[static_cast<std::size_t>(to)]) {
        cost[static_cast<std::size_t>(to)] = through;
        parent[static_cast<std::size_t>(to)] = state;
        open.emplace(through, to);
      }
    }
  }
  if (reached < 0) return {};
  std::vector<int> path;
  for (int state = reached; state >= 0; state = parent[static_cast<std::size_t>(state)]) {
    if (path.empty() || path.back() != state / kHeadings) path.push_back(state / kHeadings);
  }
  std::reverse(path.begin(), path.end());
  return path;
}

void GuidePaths::add_flow(int robot, int sign) {
  const auto& path = path_[static_cast<std::size_t>(robot)];
  for (std::size_t j = passed_[static_cast<std::size_t>(robot)]; j + 1 < path.size(); ++j) {
    const int heading = map_.heading_between(path[j], path[j + 1]);
    auto& f = flow_[static_cast<std::size_t>(path[j]) * kHeadings + static_cast<std::size_t>(heading)];
    f = static_cast<std::uint16_t>(f + sign);
  }
}

void GuidePaths::build_field(int robot) {
  const auto& path = path_[static_cast<std::size_t>(robot)];
  auto& field = field_[static_cast<std::size_t>(robot)];
  const std::size_t states = static_cast<std::size_t>(map_.cells()) * kHeadings;
  field.assign(states, kUnreachable);
  if (path.empty()) return;
  // Breadth-first backwards over (cell, heading) from every state on the path at once, the goal's
  // end first so that of two path cells equally near, the one nearer the goal is taken. A state's
  // value is its actions to the path plus the path's actions left from where it joins: the cells
  // left, the quarter turns to face the path's next cell there and those at its corners beyond.
  std::vector<std::uint16_t> reached(states, kUnreachable);
  std::vector<std::uint16_t> left(states, 0);
  std::vector<int> queue;
  queue.reserve(states);
  const int last = static_cast<int>(path.size()) - 1;
  int turns_beyond = 0;  // the quarter turns the path takes after the cell at hand
  for (int i = last; i >= 0; --i) {
    const int cell = path[static_cast<std::size_t>(i)];
    const int onward = i < last ? map_.heading_between(cell, path[static_cast<std::size_t>(i) + 1]) : -1;
    for (int h = 0; h < kHeadings; ++h) {
      const int state = cell * kHeadings + h;
      if (reached[static_cast<std::size_t>(state)] != kUnreachable) continue;  // the path crosses itself
      reached[static_cast<std::size_t>(state)] = 0;
      left[static_cast<std::size_t>(state)] =
          static_cast<std::uint16_t>((last - i) + turns_beyond + (onward >= 0 ? quarter_turns(h, onward) : 0));
      queue.push_back(state);
    }
    if (i > 0 && onward >= 0) {
      turns_beyond += quarter_turns(map_.heading_between(path[static_cast<std::size_t>(i) - 1], cell), onward);
    }
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int state = queue[head];
    const auto d = static_cast<std::uint16_t>(reached[static_cast<std::size_t>(state)] + 1);
    for (const int p : map_.predecessors(state)) {
      if (p < 0 || reached[static_cast<std::size_t>(p)] != kUnreachable) continue;
      reached[static_cast<std::size_t>(p)] = d;
      left[static_cast<std::size_t>(p)] = left[static_cast<std::size_t>(state)];
      queue.push_back(p);
    }
  }
  for (std::size_t s = 0; s < states; ++s) {
    if (reached[s] != kUnreachable) {
      field[s] = static_cast<std::uint16_t>(std::min<int>(kUnreachable - 1, reached[s] + left[s]));
    }
  }
}

void GuidePaths::assign(int robot, int cell, int heading, int goal) {
  const auto r = static_cast<std::size_t>(robot);
  add_flow(robot, -1);
  goal_[r] = goal;
  passed_[r] = 0;
  path_[r] = goal >= 0 ? search(cell, heading, goal) : std::vector<int>{};
  add_flow(robot, +1);
  build_field(robot);
}

void GuidePaths::advance(int robot, int cell) {
  const auto r = static_cast<std::size_t>(robot);
  const auto& path = path_[r];
  for (std::size_t j = passed_[r] + 1; j < path.size(); ++j) {
    if (path[j] != cell) continue;
    for (std::size_t k = passed_[r]; k < j; ++k) {
      const int heading = map_.heading_between(path[k], path[k + 1]);
      --flow_[static_cast<std::size_t>(path[k]) * kHeadings + static_cast<std::size_t>(heading)];
    }
    passed_[r] = j;
    return;
  }
}

void GuidePaths::refine(const std::vector<int>& cells, const std::vector<int>& headings, int count) {
  const std::size_t n = path_.size();
  for (std::size_t tried = 0; tried < n && count > 0; ++tried) {
    const int robot = static_cast<int>(next_refined_);
    next_refined_ = (next_refined_ + 1) % n;
    if (goal_[static_cast<std::size_t>(robot)] < 0) continue;
    assign(robot, cells[static_cast<std::size_t>(robot)], headings[static_cast<std::size_t>(robot)],
           goal_[static_cast<std::size_t>(robot)]);
    --count;
  }
}

long GuidePaths::contraflow() const {
  long sum = 0;
  for (int cell = 0; cell < map_.cells(); ++cell) {
    for (int h = 0; h < 2; ++h) {  // east and south: each pair of opposite moves once
      const int next = map_.step(cell, h);
      if (next >= 0) sum += static_cast<long>(flow(cell, h)) * flow(next, opposite(h));
    }
  }
  return sum;
}

}  // namespace fleet::coordination
