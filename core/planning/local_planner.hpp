#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "planning/dynamic_grid.hpp"
#include "planning/road_planner.hpp"
#include "planning/static_grid.hpp"

namespace fleet::planning {

/// Fixed per LocalPlanner.
struct LocalPlannerConfiguration {
  double min_lookahead = 1.0;         ///< metres checked ahead at low speed (1 m [Forklift thesis, section 5.3])
  double lookahead_time = 2.0;        ///< s; the checked distance is max(min_lookahead, speed x this)
  double temporary_size = 0.3;        ///< least side of a temporary obstacle's box, metres
  double max_temporary_extent = 1.5;  ///< metres from the collision point a temporary box may reach
  int clear_cycles = 3;               ///< consecutive cycles a temporary must be seen free before removal
  std::string id_prefix = "tmp";      ///< temporary obstacle ids are "<prefix>-<n>"
};

/// What one cycle decided.
struct LocalStep {
  PlanStatus status = PlanStatus::kNoPath;  ///< of the global plan now in force
  bool replanned = false;
  bool collision_ahead = false;      ///< the plan in force still meets an obstacle within the lookahead
  double free_distance = 0.0;        ///< metres along the plan before the first predicted collision
  std::vector<std::string> added;    ///< temporary obstacles added this cycle
  std::vector<std::string> removed;  ///< temporary obstacles removed this cycle
};

/// Local planning [Forklift thesis, section 5.3, Fig. 5.12-5.13], called once per control cycle.
///
/// The next stretch of the global plan is checked against the dynamic layer; on a predicted
/// collision a temporary static obstacle goes into the static grid there and the road planner
/// replans around it (or up to it, Forklift thesis, Fig. 5.11). A temporary obstacle is removed once its area has
/// been seen free for `clear_cycles` cycles, and the plan is made again. Any change of the static
/// grid (an operator's obstacle, too) triggers a replan.
///
/// Not thread-safe; holds references to the grid and planner it drives, which must outlive it.
class LocalPlanner {
 public:
  LocalPlanner(const LocalPlannerConfiguration& configuration, StaticGrid& static_grid, RoadPlanner& road_planner);

  void set_goal(const geometry::Pose2& goal);
  void clear_goal();
  bool has_goal() const { return goal_.has_value(); }

  LocalStep step(const geometry::Pose2& pose, double speed, const DynamicGrid& dynamic);

  const RoadPlan& plan() const { return plan_; }
  const std::map<std::string, geometry::Polygon>& own_temporaries() const { return temporaries_; }

 private:
  void replan(const geometry::Pose2& pose);
  /// Distance along the plan from `pose` to the first occupied sample, or nullopt within `lookahead`.
  std::optional<std::pair<double, geometry::Vec2>> first_collision(const geometry::Pose2& pose, double lookahead,
                                                                   const OccupancyGrid& layer) const;

  LocalPlannerConfiguration configuration_;
  StaticGrid& static_grid_;
  RoadPlanner& road_planner_;
  std::optional<geometry::Pose2> goal_;
  RoadPlan plan_;
  std::uint64_t planned_revision_ = 0;
  bool dirty_ = true;
  std::map<std::string, geometry::Polygon> temporaries_;
  std::map<std::string, int> seen_free_;
  int next_id_ = 1;
};

}  // namespace fleet::planning
