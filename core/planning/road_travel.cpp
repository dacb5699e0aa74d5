#include "planning/road_travel.hpp"

#include <limits>

namespace fleet::planning {

double road_travel_distance(RoadPlanner& planner, const geometry::Pose2& from, const geometry::Pose2& to) {
  const RoadPlan plan = planner.plan(from, to);
  if (plan.status != PlanStatus::kFound || plan.points.empty()) return std::numeric_limits<double>::infinity();
  return geometry::distance(from.position(), plan.points.front()) + plan.length +
         geometry::distance(plan.points.back(), to.position());
}

}  // namespace fleet::planning
