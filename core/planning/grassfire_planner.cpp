#include "planning/grassfire_planner.hpp"

#include <algorithm>
#include <limits>

namespace fleet::planning {

using geometry::Vec2;

namespace {

// Descent directions: the four straight ones, then the diagonals.
constexpr int kStepX[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kStepY[8] = {0, 0, 1, -1, 1, -1, 1, -1};

// Reading the clock costs tens of nanoseconds; the wave expands a cell in a few.
constexpr std::size_t kWaveCheckEvery = 1024;
constexpr std::size_t kDescentCheckEvery = 4096;

}  // namespace

void GrassfirePlanner::set_grid(std::shared_ptr<const OccupancyGrid> grid) {
  grid_ = std::move(grid);
  goal_ = -1;
  front_ = 0;
  wave_.clear();
  if (!grid_) {
    stride_ = 0;
    blank_.clear();
    values_.clear();
    return;
  }
  // [Picker thesis, section 4.3.1.2]: free cells start at -1, obstacles at -10. A one-cell
  // obstacle border keeps the wave and the descent inside the grid without bounds checks.
  stride_ = grid_->width() + 2;
  blank_.assign(static_cast<std::size_t>(stride_) * (grid_->height() + 2), kObstacle);
  for (int y = 0; y < grid_->height(); ++y) {
    for (int x = 0; x < grid_->width(); ++x) {
      if (!grid_->occupied(x, y)) blank_[static_cast<std::size_t>(y + 1) * stride_ + x + 1] = kUnreached;
    }
  }
  values_ = blank_;
  // Every free cell enters the wave at most once, so it never reallocates while burning.
  wave_.reserve(blank_.size());
}

bool GrassfirePlanner::free_cell(Vec2 p, std::int32_t& padded) const {
  const CellIndex c = grid_->cell_of(p);
  if (!grid_->in_bounds(c.x, c.y)) return false;
  padded = (c.y + 1) * stride_ + c.x + 1;
  return blank_[static_cast<std::size_t>(padded)] != kObstacle;
}

Vec2 GrassfirePlanner::center(std::int32_t padded) const {
  return grid_->cell_center(padded % stride_ - 1, padded / stride_ - 1);
}

void GrassfirePlanner::restart_wave(std::int32_t goal) {
  std::copy(blank_.begin(), blank_.end(), values_.begin());
  wave_.clear();
  front_ = 0;
  values_[static_cast<std::size_t>(goal)] = 0;
  wave_.push_back(goal);
  goal_ = goal;
}

// [Picker thesis, Algorithm 1] as order propagation: the thesis rescans the whole map once per
// distance value (O(cells x longest distance)); a FIFO of the fire front visits the cells in the
// same order of increasing distance and gives the same values in O(cells). A cell's value is final
// when it is labelled, so the wave may stop as soon as the target is labelled: every cell nearer
// the goal is labelled by then, which is all the descent from the target reads.
PlanStatus GrassfirePlanner::grow_wave(std::int32_t target, const Deadline* deadline, std::size_t node_cap,
                                       std::size_t& expanded) {
  const std::int32_t neighbours[4] = {1, -1, stride_, -stride_};
  while (target < 0 || values_[static_cast<std::size_t>(target)] < 0) {
    // The thesis loops while any free cell holds -1, which never ends when the goal cannot reach
    // one; an empty fire front is the end of the transform.
    if (front_ == wave_.size()) return PlanStatus::kNoPath;
    if (expanded >= node_cap) return PlanStatus::kTimeout;
    if (deadline != nullptr && expanded % kWaveCheckEvery == 0) {
      const PlanStatus status = deadline->check();
      if (status != PlanStatus::kFound) return status;
    }
    const std::int32_t cell = wave_[front_++];
    ++expanded;
    const std::int32_t next = values_[static_cast<std::size_t>(cell)] + 1;
    for (const std::int32_t offset : neighbours) {
      std::int32_t& value = values_[static_cast<std::size_t>(cell + offset)];
      if (value == kUnreached) {
        value = next;
        wave_.push_back(cell + offset);
      }
    }
  }
  return PlanStatus::kFound;
}

// [Picker thesis, Algorithm 2]: from the start, step to the 8-neighbour with the least value
// until the goal's 0. Two choices the thesis leaves open:
// - a diagonal step between two obstacle cells would squeeze through a gap narrower than the
//   inflation assumes, so a diagonal needs both side cells free;
// - among equal least values the thesis keeps the first in scan order; here the current heading
//   wins, then the fixed order above, so the path turns only where it must and has fewer waypoints.
// Every labelled cell but the goal has a straight neighbour one less (the one that labelled it),
// so each step goes down and the descent ends at the goal.
PlanStatus GrassfirePlanner::descend(std::int32_t from, const Deadline& deadline,
                                     std::vector<std::int32_t>& cells) const {
  cells.assign(1, from);
  std::int32_t cell = from;
  int heading = -1;
  auto value = [&](std::int32_t i) { return values_[static_cast<std::size_t>(i)]; };
  while (value(cell) > 0) {
    if (cells.size() % kDescentCheckEvery == 0) {
      const PlanStatus status = deadline.check();
      if (status != PlanStatus::kFound) return status;
    }
    int best_direction = -1;
    std::int32_t best = value(cell);
    for (int k = -1; k < 8; ++k) {
      const int d = k < 0 ? heading : k;
      if (d < 0) continue;
      const std::int32_t side_x = cell + kStepX[d];
      const std::int32_t side_y = cell + kStepY[d] * stride_;
      const std::int32_t v = value(side_x + kStepY[d] * stride_);
      if (v < 0 || v >= best) continue;
      const bool diagonal = kStepX[d] != 0 && kStepY[d] != 0;
      if (diagonal && (value(side_x) == kObstacle || value(side_y) == kObstacle)) continue;
      best = v;
      best_direction = d;
    }
    // Unreachable with a consistent transform; a guard against looping on a corrupted one.
    if (best_direction < 0) return PlanStatus::kNoPath;
    heading = best_direction;
    cell += kStepX[heading] + kStepY[heading] * stride_;
    cells.push_back(cell);
  }
  return PlanStatus::kFound;
}

// Waypoints at the turns of the cell path and at the goal [Picker thesis, section 4.3.1.2]: the
// exact start, the centres of the first cell, of every cell where the step direction changes and
// of the goal cell, then the exact goal. Straight runs between them cross only path cells.
std::vector<Vec2> GrassfirePlanner::waypoints(const std::vector<std::int32_t>& cells, Vec2 start, Vec2 goal) const {
  std::vector<Vec2> points;
  points.push_back(start);
  points.push_back(center(cells.front()));
  for (std::size_t i = 1; i + 1 < cells.size(); ++i) {
    if (cells[i] - cells[i - 1] != cells[i + 1] - cells[i]) points.push_back(center(cells[i]));
  }
  if (cells.size() > 1) points.push_back(center(cells.back()));
  points.push_back(goal);
  // The start and goal lie anywhere in their cells; going through the cell centres would add a
  // jog of up to half a cell. Skip a centre where the straight line past it stays free.
  if (points.size() > 2 && grid_->segment_free(points[0], points[2])) points.erase(points.begin() + 1);
  const std::size_t n = points.size();
  if (n > 2 && grid_->segment_free(points[n - 3], points[n - 1])) points.erase(points.end() - 2);
  points.erase(
      std::unique(points.begin(), points.end(), [](Vec2 a, Vec2 b) { return geometry::distance(a, b) < 1e-9; }),
      points.end());
  return points;
}

GridPath GrassfirePlanner::plan(Vec2 start, Vec2 goal, const PlanOptions& options) {
  GridPath result;
  std::int32_t from = -1;
  std::int32_t to = -1;
  if (!grid_ || !free_cell(start, from) || !free_cell(goal, to)) {
    result.status = PlanStatus::kInvalidStart;
    return result;
  }
  const Deadline deadline(options);
  // Checked before any reuse, so a raised flag stops even a query the cache could answer.
  result.status = deadline.check();
  if (result.status != PlanStatus::kFound) return result;
  if (to != goal_) restart_wave(to);
  result.status = grow_wave(from, &deadline, options.node_cap, result.expanded);
  if (result.status != PlanStatus::kFound) return result;
  std::vector<std::int32_t> cells;
  result.status = descend(from, deadline, cells);
  if (result.status != PlanStatus::kFound) return result;
  result.points = waypoints(cells, start, goal);
  result.length = path_length(result.points);
  return result;
}

std::vector<std::int32_t> GrassfirePlanner::complete_transform(Vec2 goal) {
  std::int32_t to = -1;
  if (!grid_ || !free_cell(goal, to)) return {};
  if (to != goal_) restart_wave(to);
  std::size_t expanded = 0;
  grow_wave(-1, nullptr, std::numeric_limits<std::size_t>::max(), expanded);
  std::vector<std::int32_t> values;
  values.reserve(grid_->size());
  for (int y = 0; y < grid_->height(); ++y) {
    const auto row = values_.begin() + static_cast<std::ptrdiff_t>(y + 1) * stride_ + 1;
    values.insert(values.end(), row, row + grid_->width());
  }
  return values;
}

}  // namespace fleet::planning
