#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::planning {

struct CellIndex {
  int x = 0;
  int y = 0;
  friend bool operator==(CellIndex, CellIndex) = default;
};

/// A binary occupancy grid over a rectangle of the map frame, row-major from (min_x, min_y).
/// The thesis keeps binary values ("absence or presence of the obstacle is denoted by either 0 or
/// 1" [Forklift thesis, section 5.3]); probabilities live in the OctoMap layer and are thresholded here.
class OccupancyGrid {
 public:
  static constexpr std::uint8_t kFree = 0;
  static constexpr std::uint8_t kOccupied = 1;

  OccupancyGrid() = default;
  /// Covers `bounds` with square cells of `resolution` metres, every cell set to `fill`.
  /// Throws std::invalid_argument for a non-positive resolution or empty bounds.
  OccupancyGrid(const geometry::Bounds& bounds, double resolution, std::uint8_t fill = kFree);

  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t size() const { return cells_.size(); }
  double resolution() const { return resolution_; }
  geometry::Vec2 origin() const { return origin_; }
  geometry::Bounds bounds() const;

  bool in_bounds(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  /// The cell holding `p` (may be outside the grid).
  CellIndex cell_of(geometry::Vec2 p) const;
  geometry::Vec2 cell_center(int x, int y) const;
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }

  /// Cells outside the grid count as occupied: nothing may leave the map.
  bool occupied(int x, int y) const { return !in_bounds(x, y) || cells_[index(x, y)] != kFree; }
  bool occupied_at(geometry::Vec2 p) const {
    const CellIndex c = cell_of(p);
    return occupied(c.x, c.y);
  }
  void set(int x, int y, bool occupied) {
    if (in_bounds(x, y)) cells_[index(x, y)] = occupied ? kOccupied : kFree;
  }
  void fill(std::uint8_t value);

  const std::vector<std::uint8_t>& cells() const { return cells_; }
  std::vector<std::uint8_t>& cells() { return cells_; }

  /// Sets every cell whose centre lies inside `polygon`. Marking occupied is conservative: the
  /// cells its edges pass through are marked too, so an obstacle thinner than a cell still shows.
  void fill_polygon(const geometry::Polygon& polygon, bool occupied);
  /// Sets every cell whose centre lies within `radius` of `center`; the centre's cell always.
  void fill_disc(geometry::Vec2 center, double radius, bool occupied);
  /// Sets every cell the segment passes through (supercover).
  void fill_segment(geometry::Vec2 a, geometry::Vec2 b, bool occupied);

  /// A copy whose occupied cells are grown by `radius` metres (a disc of cell offsets).
  OccupancyGrid dilated(double radius) const;
  /// Grows the occupied cells by `radius` metres in place, as dilated() does.
  void dilate(double radius);
  /// Every cell occupied in `a` or `b` (of the same geometry) occupied, the rest free; the storage
  /// is reused when this grid already has their geometry.
  void assign_union(const OccupancyGrid& a, const OccupancyGrid& b);
  /// Every cell free.
  void clear() { std::fill(cells_.begin(), cells_.end(), kFree); }

  /// True when every cell the segment passes through is free. Where the segment crosses a cell
  /// corner exactly, both side cells must be free, so a path never squeezes between diagonal
  /// obstacles.
  bool segment_free(geometry::Vec2 a, geometry::Vec2 b) const;

  std::size_t occupied_count() const;
  bool same_geometry(const OccupancyGrid& other) const;

 private:
  template <typename Visit>
  bool traverse(geometry::Vec2 a, geometry::Vec2 b, Visit&& visit) const;

  geometry::Vec2 origin_;
  double resolution_ = 0.0;
  int width_ = 0;
  int height_ = 0;
  std::vector<std::uint8_t> cells_;
};

}  // namespace fleet::planning
