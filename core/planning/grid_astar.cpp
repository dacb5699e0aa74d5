#include "planning/grid_astar.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleet::planning {

using geometry::Vec2;

namespace {

constexpr float kSqrt2Minus1 = 0.41421356f;

bool heap_less(const auto& a, const auto& b) {
  // Min-heap on f; equal f: larger g first, the node nearer the goal.
  return a.f > b.f || (a.f == b.f && a.g < b.g);
}

int sign(int v) {
  return (v > 0) - (v < 0);
}

}  // namespace

double path_length(const std::vector<Vec2>& points) {
  double len = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) len += geometry::distance(points[i - 1], points[i]);
  return len;
}

GridAStar::GridAStar(const GridAStarConfiguration& configuration) : configuration_(configuration) {}

void GridAStar::set_grid(std::shared_ptr<const OccupancyGrid> grid) {
  grid_ = std::move(grid);
  if (!grid_) {
    stride_ = 0;
    passable_.clear();
    return;
  }
  stride_ = grid_->width() + 2;
  const std::size_t n = static_cast<std::size_t>(stride_) * (grid_->height() + 2);
  passable_.assign(n, 0);
  for (int y = 0; y < grid_->height(); ++y) {
    for (int x = 0; x < grid_->width(); ++x) {
      passable_[static_cast<std::size_t>(y + 1) * stride_ + x + 1] = grid_->occupied(x, y) ? 0 : 1;
    }
  }
  build_jump_tables();
  stamp_.assign(n, 0);
  g_.assign(n, 0.0f);
  parent_.assign(n, -1);
  query_ = 0;
}

float GridAStar::heuristic(std::int32_t a, std::int32_t b) const {
  // Octile distance: the exact cost of an 8-connected path on an empty grid.
  const int dx = std::abs(a % stride_ - b % stride_);
  const int dy = std::abs(a / stride_ - b / stride_);
  return static_cast<float>(std::max(dx, dy)) + kSqrt2Minus1 * static_cast<float>(std::min(dx, dy));
}

Vec2 GridAStar::center(std::int32_t i) const {
  return grid_->cell_center(i % stride_ - 1, i / stride_ - 1);
}

// Straight jumps are table lookups (the straight half of JPS+, Harabor and Grastien, ICAPS 2012):
// for every cell and straight direction, the steps to the first cell with a forced neighbour, or
// -1 when a wall comes first. Without them a long empty corridor is re-scanned at every diagonal
// step; with them a diagonal walk costs O(1) per step.
void GridAStar::build_jump_tables() {
  const std::int32_t s = stride_;
  const std::int32_t n = static_cast<std::int32_t>(passable_.size());
  const std::int32_t delta[4] = {1, -1, s, -s};
  for (int d = 0; d < 4; ++d) {
    auto& table = straight_[d];
    table.assign(passable_.size(), -1);
    const std::int32_t step = delta[d];
    const bool horizontal = d < 2;
    const std::int32_t back = -step;
    // Sweep against the direction of travel, so the cell ahead is already known.
    const bool forward = step > 0;
    for (std::int32_t k = 0; k < n; ++k) {
      const std::int32_t c = forward ? n - 1 - k : k;
      if (!free(c)) continue;  // stays -1
      const std::int32_t side_a = horizontal ? c - s : c - 1;
      const std::int32_t side_b = horizontal ? c + s : c + 1;
      const bool forced = (free(side_a) && !free(side_a + back)) || (free(side_b) && !free(side_b + back));
      if (forced) {
        table[c] = 0;
      } else {
        const std::int32_t ahead = c + step;
        table[c] = (ahead >= 0 && ahead < n && free(ahead) && table[ahead] >= 0) ? table[ahead] + 1 : -1;
      }
    }
  }
}

std::int32_t GridAStar::jump_straight(std::int32_t from, int d, std::int32_t goal) const {
  if (!free(from)) return -1;
  const std::int32_t s = stride_;
  const std::int32_t k = straight_[d][from];
  // The goal, when it lies on this ray before the jump point (or the wall), ends the jump there.
  const bool horizontal = d < 2;
  const bool same_line = horizontal ? goal / s == from / s : goal % s == from % s;
  if (same_line) {
    const std::int32_t step = d == 0 ? 1 : d == 1 ? -1 : d == 2 ? s : -s;
    const std::int32_t dist = (goal - from) / step;
    if (dist >= 0 && (k < 0 ? true : dist <= k)) {
      // Without a jump point ahead, the goal still has to be reachable before the wall.
      if (k >= 0) return goal;
      bool clear = true;
      for (std::int32_t c = from; c != goal; c += step) {
        if (!free(c)) {
          clear = false;
          break;
        }
      }
      if (clear && free(goal)) return goal;
    }
  }
  return k >= 0 ? from + k * (d == 0 ? 1 : d == 1 ? -1 : d == 2 ? s : -s) : -1;
}

// Jump point search with the "no corner cutting" movement rule: from `from` (already one step
// away from its parent in direction (dx, dy)) walk on until a node with a forced neighbour, the
// goal, or a wall. Diagonal walks look for jump points along both straight directions first.
std::int32_t GridAStar::jump(std::int32_t from, int dx, int dy, std::int32_t goal) const {
  const std::int32_t s = stride_;
  if (dx == 0 || dy == 0) return jump_straight(from, dx > 0 ? 0 : dx < 0 ? 1 : dy > 0 ? 2 : 3, goal);
  const int dir_x = dx > 0 ? 0 : 1;
  const int dir_y = dy > 0 ? 2 : 3;
  std::int32_t cur = from;
  while (true) {
    if (!free(cur)) return -1;
    if (cur == goal) return cur;
    if (jump_straight(cur + dx, dir_x, goal) >= 0 || jump_straight(cur + dy * s, dir_y, goal) >= 0) return cur;
    if (!free(cur + dx) || !free(cur + dy * s)) return -1;
    cur += dx + dy * s;
  }
}

void GridAStar::push(std::int32_t node, float g, std::int32_t parent, std::int32_t goal) {
  if (stamp_[node] != query_) {
    stamp_[node] = query_;
    g_[node] = std::numeric_limits<float>::infinity();
  }
  if (g < g_[node]) {
    g_[node] = g;
    parent_[node] = parent;
    heap_.push_back({g + heuristic(node, goal), g, node});
    std::push_heap(heap_.begin(), heap_.end(), [](const HeapItem& a, const HeapItem& b) { return heap_less(a, b); });
  }
}

int GridAStar::pruned_directions(std::int32_t n, int (&dirs)[8][2]) const {
  int count = 0;
  const std::int32_t s = stride_;
  const std::int32_t p = parent_[n];
  if (p < 0) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        if (dx != 0 && dy != 0 && (!free(n + dx) || !free(n + dy * s))) continue;
        dirs[count][0] = dx;
        dirs[count][1] = dy;
        ++count;
      }
    }
  } else {
    const int dx = sign(n % s - p % s);
    const int dy = sign(n / s - p / s);
    auto add = [&](int ax, int ay) {
      dirs[count][0] = ax;
      dirs[count][1] = ay;
      ++count;
    };
    if (dx != 0 && dy != 0) {
      const bool side_y = free(n + dy * s);
      const bool side_x = free(n + dx);
      if (side_y) add(0, dy);
      if (side_x) add(dx, 0);
      if (side_y && side_x) add(dx, dy);
    } else if (dx != 0) {
      const bool next = free(n + dx);
      const bool up = free(n + s);
      const bool down = free(n - s);
      if (next) {
        add(dx, 0);
        if (up) add(dx, 1);
        if (down) add(dx, -1);
      }
      if (up) add(0, 1);
      if (down) add(0, -1);
    } else {
      const bool next = free(n + dy * s);
      const bool right = free(n + 1);
      const bool left = free(n - 1);
      if (next) {
        add(0, dy);
        if (right) add(1, dy);
        if (left) add(-1, dy);
      }
      if (right) add(1, 0);
      if (left) add(-1, 0);
    }
  }
  return count;
}

void GridAStar::expand(std::int32_t n, std::int32_t dst, std::uint32_t closed) {
  const std::int32_t s = stride_;
  const float gn = g_[n];
  auto relax = [&](std::int32_t m, float step) {
    if (stamp_[m] != closed) push(m, gn + step, n, dst);
  };
  if (!configuration_.jump_points) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        const std::int32_t m = n + dx + dy * s;
        if (!free(m)) continue;
        if (dx != 0 && dy != 0 && (!free(n + dx) || !free(n + dy * s))) continue;
        relax(m, dx != 0 && dy != 0 ? 1.41421356f : 1.0f);
      }
    }
    return;
  }
  // Directions worth following out of n (pruned neighbours of JPS).
  int dirs[8][2];
  const int count = pruned_directions(n, dirs);
  for (int k = 0; k < count; ++k) {
    const int dx = dirs[k][0];
    const int dy = dirs[k][1];
    if (dx != 0 && dy != 0 && (!free(n + dx) || !free(n + dy * s))) continue;
    const std::int32_t j = jump(n + dx + dy * s, dx, dy, dst);
    if (j >= 0) relax(j, heuristic(n, j));
  }
}

std::vector<Vec2> GridAStar::path_points(std::int32_t dst, Vec2 start, Vec2 goal) const {
  std::vector<Vec2> points;
  // Waypoints: exact start, its cell centre, the jump points (or cells), goal's centre, exact goal.
  std::vector<std::int32_t> nodes;
  for (std::int32_t v = dst; v != -1; v = parent_[v]) nodes.push_back(v);
  std::reverse(nodes.begin(), nodes.end());
  std::vector<Vec2> raw;
  raw.reserve(nodes.size() + 2);
  raw.push_back(start);
  for (std::int32_t v : nodes) raw.push_back(center(v));
  raw.push_back(goal);
  if (configuration_.smooth && raw.size() > 2) {
    // Greedy line-of-sight shortcuts: keep a waypoint only where the straight line to the next
    // one would touch an occupied cell.
    points.push_back(raw.front());
    std::size_t anchor = 0;
    for (std::size_t i = 2; i < raw.size(); ++i) {
      if (!grid_->segment_free(raw[anchor], raw[i])) {
        anchor = i - 1;
        points.push_back(raw[anchor]);
      }
    }
    points.push_back(raw.back());
  } else {
    points = std::move(raw);
  }
  // Drop zero-length steps (start on its cell centre and the like).
  points.erase(
      std::unique(points.begin(), points.end(), [](Vec2 a, Vec2 b) { return geometry::distance(a, b) < 1e-9; }),
      points.end());
  return points;
}

GridPath GridAStar::plan(Vec2 start, Vec2 goal, const PlanOptions& options) {
  GridPath result;
  if (!grid_) {
    result.status = PlanStatus::kInvalidStart;
    return result;
  }
  const Deadline deadline(options);
  const CellIndex sc = grid_->cell_of(start);
  const CellIndex gc = grid_->cell_of(goal);
  if (grid_->occupied(sc.x, sc.y) || grid_->occupied(gc.x, gc.y)) {
    result.status = PlanStatus::kInvalidStart;
    return result;
  }
  const std::int32_t s = stride_;
  const std::int32_t src = (sc.y + 1) * s + sc.x + 1;
  const std::int32_t dst = (gc.y + 1) * s + gc.x + 1;
  // Stamps mark the entries of this query; the closed flag is the stamp's odd twin.
  query_ += 2;
  if (query_ < 2) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 2;
  }
  const std::uint32_t closed = query_ + 1;
  heap_.clear();
  push(src, 0.0f, -1, dst);
  bool found = false;
  std::size_t iterations = 0;
  while (!heap_.empty()) {
    if ((iterations++ & 127) == 0) {
      const PlanStatus st = deadline.check();
      if (st != PlanStatus::kFound) {
        result.status = st;
        return result;
      }
    }
    std::pop_heap(heap_.begin(), heap_.end(), [](const HeapItem& a, const HeapItem& b) { return heap_less(a, b); });
    const HeapItem item = heap_.back();
    heap_.pop_back();
    const std::int32_t n = item.node;
    if (stamp_[n] == closed || item.g > g_[n]) continue;
    stamp_[n] = closed;
    ++result.expanded;
    if (n == dst) {
      found = true;
      break;
    }
    if (result.expanded > options.node_cap) {
      result.status = PlanStatus::kTimeout;
      return result;
    }
    expand(n, dst, closed);
  }
  if (!found) {
    result.status = PlanStatus::kNoPath;
    return result;
  }

  result.points = path_points(dst, start, goal);
  result.length = path_length(result.points);
  result.status = PlanStatus::kFound;
  return result;
}

}  // namespace fleet::planning
