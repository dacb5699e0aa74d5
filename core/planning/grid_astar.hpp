#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "planning/grid_planner.hpp"

namespace fleet::planning {

/// Fixed per GridAStar instance.
struct GridAStarConfiguration {
  /// Jump point search (Harabor and Grastien, AAAI 2011): the same optimal 8-connected paths as
  /// plain A*, found by expanding only jump points. Off: textbook A*, kept as the reference.
  bool jump_points = true;
  /// Shorten the cell path by line-of-sight shortcuts on the grid (any-angle post-smoothing).
  bool smooth = true;
};

/// A* on an 8-connected grid with the octile heuristic. A diagonal step needs both side cells
/// free, so a path never cuts an obstacle's corner.
///
/// The grid is copied once into a padded byte array (a one-cell occupied border removes every
/// bounds check from the inner loop) and the straight jumps are tabulated then, so `set_grid`
/// costs a few milliseconds on 320k cells and queries after it run without rescanning corridors;
/// search buffers are reused and reset lazily by a query stamp.
class GridAStar final : public GridPlanner {
 public:
  explicit GridAStar(const GridAStarConfiguration& configuration = {});

  std::string name() const override { return "grid_astar"; }
  void set_grid(std::shared_ptr<const OccupancyGrid> grid) override;
  GridPath plan(geometry::Vec2 start, geometry::Vec2 goal, const PlanOptions& options) override;

 private:
  struct HeapItem {
    float f;
    float g;
    std::int32_t node;
  };

  bool free(std::int32_t i) const { return passable_[static_cast<std::size_t>(i)] != 0; }
  std::int32_t jump(std::int32_t from, int dx, int dy, std::int32_t goal) const;
  /// Direction d: 0 +x, 1 -x, 2 +y, 3 -y.
  std::int32_t jump_straight(std::int32_t from, int d, std::int32_t goal) const;
  void build_jump_tables();
  void push(std::int32_t node, float g, std::int32_t parent, std::int32_t goal);
  /// Pushes the successors of node `n` (all eight neighbours, or JPS's jump points) that are not
  /// `closed` in this query.
  void expand(std::int32_t n, std::int32_t dst, std::uint32_t closed);
  /// The directions worth following out of `n` (the pruned neighbours of JPS); their count.
  int pruned_directions(std::int32_t n, int (&dirs)[8][2]) const;
  /// Exact start, its cell centre, the cells (or jump points) to `dst`, the goal's centre and the
  /// exact goal, smoothed when configured, without zero-length steps.
  std::vector<geometry::Vec2> path_points(std::int32_t dst, geometry::Vec2 start, geometry::Vec2 goal) const;
  float heuristic(std::int32_t a, std::int32_t b) const;
  geometry::Vec2 center(std::int32_t i) const;

  GridAStarConfiguration configuration_;
  std::shared_ptr<const OccupancyGrid> grid_;
  int stride_ = 0;  ///< padded width
  std::vector<std::uint8_t> passable_;
  std::vector<std::int32_t> straight_[4];  ///< steps to the next straight jump point, -1: wall first
  std::vector<std::uint32_t> stamp_;
  std::vector<float> g_;
  std::vector<std::int32_t> parent_;
  std::vector<HeapItem> heap_;
  std::uint32_t query_ = 0;
};

}  // namespace fleet::planning
