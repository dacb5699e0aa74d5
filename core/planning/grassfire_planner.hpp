#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "planning/grid_planner.hpp"

namespace fleet::planning {

/// The picker's global planner [Picker thesis, section 4.3.1]: a grassfire distance transform
/// spreads from the goal over the free cells, 4 neighbours, +1 per cell [Picker thesis, Algorithm 1];
/// the path is its steepest descent from the start over 8 neighbours [Picker thesis, Algorithm 2],
/// with a waypoint wherever the descent turns and at the goal.
///
/// Cost: the transform is O(cells) per goal and does not depend on the start. It grows from the
/// goal only until it reaches the start, and is kept for the last goal: a later query to the same
/// goal cell on the same grid resumes it (or reuses it as it is when the start is already labelled)
/// and then pays only the descent, O(path cells). `set_grid` forgets it.
///
/// Bounds: `PlanOptions::node_cap` caps the cells the transform expands in one query, so a cached
/// query that expands none always completes. A query stopped by the cap, the time budget or the
/// cancel flag leaves a valid partial transform that the next query to the same goal resumes.
///
/// Path: the transform measures 4-neighbour steps, so the descent takes a diagonal step (two
/// units down) wherever it can. A diagonal step needs both side cells free, as in `GridAStar`, so
/// a path never cuts an obstacle's corner. The descent path is at most sqrt(2) times as long as
/// the shortest 8-connected path, and equal to it on an open floor.
///
/// The grid is copied once into a padded array of the thesis's cell values, so the wave needs no
/// bounds checks. Thread safety: as `GridPlanner`.
class GrassfirePlanner final : public GridPlanner {
 public:
  /// Cell values of the transform [Picker thesis, section 4.3.1.2]: a free cell not (yet) reached
  /// by the wave, and an obstacle. Reached cells hold their distance from the goal in cells.
  static constexpr std::int32_t kUnreached = -1;
  static constexpr std::int32_t kObstacle = -10;

  std::string name() const override { return "grassfire"; }
  void set_grid(std::shared_ptr<const OccupancyGrid> grid) override;
  GridPath plan(geometry::Vec2 start, geometry::Vec2 goal, const PlanOptions& options) override;

  /// The whole transform for `goal`, row-major like the grid's cells: kObstacle for occupied cells,
  /// kUnreached for free cells the goal cannot reach. Unbounded (O(cells)); it becomes the cached
  /// transform, so every later start to this goal costs only its descent. Empty without a grid or
  /// for a goal outside the grid or in an obstacle.
  std::vector<std::int32_t> complete_transform(geometry::Vec2 goal);

 private:
  /// The padded index of the cell holding `p`; false when `p` is outside the grid or occupied.
  bool free_cell(geometry::Vec2 p, std::int32_t& padded) const;
  /// Starts a new transform: the goal cell at 0, every other free cell kUnreached.
  void restart_wave(std::int32_t goal);
  /// Burns on until `target` is labelled (kFound) or, for target -1, until nothing is left. Stops
  /// with kNoPath when the wave burns out first, kTimeout at the node cap, or the deadline's status.
  PlanStatus grow_wave(std::int32_t target, const Deadline* deadline, std::size_t node_cap, std::size_t& expanded);
  /// The cells from `from` down to the goal; kFound, or the deadline's status.
  PlanStatus descend(std::int32_t from, const Deadline& deadline, std::vector<std::int32_t>& cells) const;
  std::vector<geometry::Vec2> waypoints(const std::vector<std::int32_t>& cells, geometry::Vec2 start,
                                        geometry::Vec2 goal) const;
  geometry::Vec2 center(std::int32_t padded) const;

  std::shared_ptr<const OccupancyGrid> grid_;
  int stride_ = 0;                    ///< padded width
  std::vector<std::int32_t> blank_;   ///< kUnreached or kObstacle per padded cell; the border is kObstacle
  std::vector<std::int32_t> values_;  ///< the transform of `goal_`, partial while the wave burns
  std::vector<std::int32_t> wave_;    ///< cells in the order they were reached: a FIFO read from `front_`
  std::size_t front_ = 0;
  std::int32_t goal_ = -1;  ///< padded index of the cached goal cell; -1: none
};

}  // namespace fleet::planning
