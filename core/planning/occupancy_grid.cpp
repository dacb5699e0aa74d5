#include "planning/occupancy_grid.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace fleet::planning {

using geometry::Vec2;

OccupancyGrid::OccupancyGrid(const geometry::Bounds& bounds, double resolution, std::uint8_t fill)
    : origin_{bounds.min_x, bounds.min_y}, resolution_(resolution) {
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    throw std::invalid_argument("occupancy grid: resolution must be positive, got " + std::to_string(resolution));
  }
  if (!(bounds.max_x > bounds.min_x) || !(bounds.max_y > bounds.min_y)) {
    throw std::invalid_argument("occupancy grid: bounds are empty");
  }
  // A small tolerance keeps 3.0 / 0.02 from becoming 151 cells through rounding.
  width_ = static_cast<int>(std::ceil((bounds.max_x - bounds.min_x) / resolution - 1e-9));
  height_ = static_cast<int>(std::ceil((bounds.max_y - bounds.min_y) / resolution - 1e-9));
  cells_.assign(static_cast<std::size_t>(width_) * height_, fill);
}

geometry::Bounds OccupancyGrid::bounds() const {
  return {origin_.x, origin_.y, origin_.x + width_ * resolution_, origin_.y + height_ * resolution_};
}

CellIndex OccupancyGrid::cell_of(Vec2 p) const {
  return {static_cast<int>(std::floor((p.x - origin_.x) / resolution_)),
          static_cast<int>(std::floor((p.y - origin_.y) / resolution_))};
}

Vec2 OccupancyGrid::cell_center(int x, int y) const {
  return {origin_.x + (x + 0.5) * resolution_, origin_.y + (y + 0.5) * resolution_};
}

void OccupancyGrid::fill(std::uint8_t value) {
  std::fill(cells_.begin(), cells_.end(), value);
}

void OccupancyGrid::fill_polygon(const geometry::Polygon& polygon, bool occupied) {
  if (polygon.size() < 3 || cells_.empty()) return;
  const geometry::Bounds box = geometry::bounding_box(polygon);
  const int y0 = std::max(0, cell_of({box.min_x, box.min_y}).y);
  const int y1 = std::min(height_ - 1, cell_of({box.max_x, box.max_y}).y);
  std::vector<double> xs;
  // Scanline through cell centres: even-odd crossings give the inside spans.
  for (int y = y0; y <= y1; ++y) {
    const double cy = origin_.y + (y + 0.5) * resolution_;
    xs.clear();
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Vec2 a = polygon[i];
      const Vec2 b = polygon[(i + 1) % polygon.size()];
      if ((a.y <= cy && b.y > cy) || (b.y <= cy && a.y > cy)) {
        xs.push_back(a.x + (cy - a.y) / (b.y - a.y) * (b.x - a.x));
      }
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t i = 0; i + 1 < xs.size(); i += 2) {
      const int xa = std::max(0, static_cast<int>(std::ceil((xs[i] - origin_.x) / resolution_ - 0.5)));
      const int xb = std::min(width_ - 1, static_cast<int>(std::floor((xs[i + 1] - origin_.x) / resolution_ - 0.5)));
      for (int x = xa; x <= xb; ++x) cells_[index(x, y)] = occupied ? kOccupied : kFree;
    }
  }
  if (occupied) {
    for (std::size_t i = 0; i < polygon.size(); ++i) fill_segment(polygon[i], polygon[(i + 1) % polygon.size()], true);
  }
}

void OccupancyGrid::fill_disc(Vec2 center, double radius, bool occupied) {
  if (cells_.empty()) return;
  const CellIndex lo = cell_of({center.x - radius, center.y - radius});
  const CellIndex hi = cell_of({center.x + radius, center.y + radius});
  const double r2 = radius * radius;
  for (int y = std::max(0, lo.y); y <= std::min(height_ - 1, hi.y); ++y) {
    for (int x = std::max(0, lo.x); x <= std::min(width_ - 1, hi.x); ++x) {
      const Vec2 c = cell_center(x, y);
      const double dx = c.x - center.x;
      const double dy = c.y - center.y;
      if (dx * dx + dy * dy <= r2) cells_[index(x, y)] = occupied ? kOccupied : kFree;
    }
  }
  const CellIndex c = cell_of(center);
  set(c.x, c.y, occupied);
}

// Amanatides and Woo's voxel traversal; at an exact corner crossing both side cells are visited.
template <typename Visit>
bool OccupancyGrid::traverse(Vec2 a, Vec2 b, Visit&& visit) const {
  CellIndex c = cell_of(a);
  const CellIndex end = cell_of(b);
  if (!visit(c.x, c.y)) return false;
  const double dx = b.x - a.x;
  const double dy = b.y - a.y;
  const int step_x = dx > 0 ? 1 : (dx < 0 ? -1 : 0);
  const int step_y = dy > 0 ? 1 : (dy < 0 ? -1 : 0);
  const double inf = std::numeric_limits<double>::infinity();
  const double t_delta_x = step_x != 0 ? resolution_ / std::abs(dx) : inf;
  const double t_delta_y = step_y != 0 ? resolution_ / std::abs(dy) : inf;
  const double fx = (a.x - origin_.x) / resolution_ - c.x;  // position inside the cell, [0, 1)
  const double fy = (a.y - origin_.y) / resolution_ - c.y;
  double t_max_x = step_x > 0 ? (1.0 - fx) * t_delta_x : (step_x < 0 ? fx * t_delta_x : inf);
  double t_max_y = step_y > 0 ? (1.0 - fy) * t_delta_y : (step_y < 0 ? fy * t_delta_y : inf);
  const int max_steps = std::abs(end.x - c.x) + std::abs(end.y - c.y) + 2;
  for (int i = 0; i < max_steps && !(c == end); ++i) {
    if (std::abs(t_max_x - t_max_y) < 1e-12) {
      if (!visit(c.x + step_x, c.y) || !visit(c.x, c.y + step_y)) return false;
      c.x += step_x;
      c.y += step_y;
      t_max_x += t_delta_x;
      t_max_y += t_delta_y;
    } else if (t_max_x < t_max_y) {
      c.x += step_x;
      t_max_x += t_delta_x;
    } else {
      c.y += step_y;
      t_max_y += t_delta_y;
    }
    if (!visit(c.x, c.y)) return false;
  }
  // Rounding can leave the walk a cell beside the end cell; the end cell is checked regardless.
  return c == end || visit(end.x, end.y);
}

void OccupancyGrid::fill_segment(Vec2 a, Vec2 b, bool occupied) {
  traverse(a, b, [&](int x, int y) {
    set(x, y, occupied);
    return true;
  });
}

bool OccupancyGrid::segment_free(Vec2 a, Vec2 b) const {
  return traverse(a, b, [&](int x, int y) { return !occupied(x, y); });
}

OccupancyGrid OccupancyGrid::dilated(double radius) const {
  OccupancyGrid out = *this;
  out.dilate(radius);
  return out;
}

void OccupancyGrid::dilate(double radius) {
  const int r = static_cast<int>(std::floor(radius / resolution_ + 1e-9));
  if (r <= 0) return;
  std::vector<CellIndex> offsets;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy <= r * r && (dx != 0 || dy != 0)) offsets.push_back({dx, dy});
    }
  }
  // Only cells on the boundary of an occupied region can grow it. They are found first, so that
  // the cells grown in place do not grow in turn.
  std::vector<CellIndex> boundary;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      // Mostly free: eight cells at a time while they are.
      if (std::uint64_t eight = 0; x + 8 <= width_ && (std::memcpy(&eight, &cells_[index(x, y)], 8), eight == 0)) {
        x += 7;
        continue;
      }
      if (cells_[index(x, y)] == kFree) continue;
      const bool interior = x > 0 && y > 0 && x + 1 < width_ && y + 1 < height_ && cells_[index(x - 1, y)] != kFree &&
                            cells_[index(x + 1, y)] != kFree && cells_[index(x, y - 1)] != kFree &&
                            cells_[index(x, y + 1)] != kFree;
      if (!interior) boundary.push_back({x, y});
    }
  }
  for (const CellIndex& c : boundary) {
    for (const CellIndex& o : offsets) {
      const int nx = c.x + o.x;
      const int ny = c.y + o.y;
      if (in_bounds(nx, ny)) cells_[index(nx, ny)] = kOccupied;
    }
  }
}

void OccupancyGrid::assign_union(const OccupancyGrid& a, const OccupancyGrid& b) {
  if (!a.same_geometry(b)) throw std::invalid_argument("occupancy grid: union of grids with different geometry");
  if (!same_geometry(a)) *this = OccupancyGrid(a.bounds(), a.resolution());
  // Without a branch and with the size in a local, so that the compiler vectorises it (bytes may
  // alias the vector's own fields): it runs over whole sites ten times a second.
  const std::size_t n = cells_.size();
  std::uint8_t* __restrict out = cells_.data();
  const std::uint8_t* __restrict first = a.cells_.data();
  const std::uint8_t* __restrict second = b.cells_.data();
  for (std::size_t i = 0; i < n; ++i) out[i] = first[i] != kFree || second[i] != kFree ? kOccupied : kFree;
}

std::size_t OccupancyGrid::occupied_count() const {
  return static_cast<std::size_t>(
      std::count_if(cells_.begin(), cells_.end(), [](std::uint8_t v) { return v != kFree; }));
}

bool OccupancyGrid::same_geometry(const OccupancyGrid& other) const {
  return width_ == other.width_ && height_ == other.height_ && resolution_ == other.resolution_ &&
         origin_ == other.origin_;
}

}  // namespace fleet::planning
