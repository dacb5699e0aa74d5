#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

#include "planning/grid_planner.hpp"

namespace fleet::planning {

enum class OmplAlgorithm {
  kRrtConnect,  ///< bidirectional RRT (Kuffner and LaValle 2000), feasible paths fast
  kRrtStar,     ///< RRT* (Karaman and Frazzoli 2011), asymptotically optimal
  kBitStar,     ///< Batch Informed Trees (Gammell et al. 2015), asymptotically optimal
};

/// Fixed per planner instance.
struct OmplPlannerConfiguration {
  OmplAlgorithm algorithm = OmplAlgorithm::kRrtConnect;
  /// Motion checks sample every this many cells: finer than a cell, so an edge cannot hop over
  /// a one-cell obstacle.
  double check_cells = 0.25;
  /// RRTConnect: shorten the found path (shortcuts, vertex reduction, smoothing) with the budget left.
  bool simplify = true;
  double range = 0.0;  ///< longest tree edge, metres; 0 keeps OMPL's default (a fifth of the extent)
};

/// An OMPL planner on an inflated occupancy grid (a point robot), in an SE2 state space whose
/// heading carries no distance weight: the grid is inflated by the robot's circumscribed radius,
/// so any heading at a free cell is valid.
///
/// Sampling comes from OMPL's process-wide generator; call `seed_ompl` once, before the first
/// planner exists, for reproducible runs. Not thread-safe: one query at a time per instance.
class OmplGridPlanner final : public GridPlanner {
 public:
  explicit OmplGridPlanner(const OmplPlannerConfiguration& configuration = {});
  ~OmplGridPlanner() override;

  /// "ompl_rrtconnect", "ompl_rrtstar" or "ompl_bitstar".
  std::string name() const override;
  void set_grid(std::shared_ptr<const OccupancyGrid> grid) override;
  /// `options.node_cap` bounds the states the planner collision-checks. RRTConnect stops at its
  /// first solution; the optimising planners use the whole time budget.
  GridPath plan(geometry::Vec2 start, geometry::Vec2 goal, const PlanOptions& options) override;

 private:
  struct Impl;
  OmplPlannerConfiguration configuration_;
  std::shared_ptr<const OccupancyGrid> grid_;
  std::unique_ptr<Impl> impl_;
};

/// Seeds OMPL's process-wide random generator. Effective only before OMPL draws its first seed.
void seed_ompl(std::uint32_t seed);
/// OMPL logs every query at "info"; keep warnings and errors only.
void quiet_ompl_logs();

}  // namespace fleet::planning
