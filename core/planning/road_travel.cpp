#include "planning/road_travel.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <queue>

namespace fleet::planning {

double road_travel_distance(RoadPlanner& planner, const geometry::Pose2& from, const geometry::Pose2& to) {
  const RoadPlan plan = planner.plan(from, to);
  if (plan.status != PlanStatus::kFound || plan.points.empty()) return std::numeric_limits<double>::infinity();
  return geometry::distance(from.position(), plan.points.front()) + plan.length +
         geometry::distance(plan.points.back(), to.position());
}

RoadDistances::RoadDistances(const map::RoadGraph& graph) : nearest_(graph), predecessors_(graph.points.size()) {
  for (std::size_t from = 0; from < graph.successors.size(); ++from) {
    const auto& a = graph.points[from];
    for (int to : graph.successors[from]) {
      const auto& b = graph.points[static_cast<std::size_t>(to)];
      predecessors_[static_cast<std::size_t>(to)].emplace_back(static_cast<int>(from),
                                                               static_cast<float>(std::hypot(b.x - a.x, b.y - a.y)));
    }
  }
}

const std::vector<float>& RoadDistances::to_point(int goal) {
  if (const auto it = fields_.find(goal); it != fields_.end()) return it->second;
  if (fields_.size() >= kKeptGoals) fields_.clear();
  std::vector<float>& field = fields_[goal];
  field.assign(predecessors_.size(), std::numeric_limits<float>::infinity());
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  field[static_cast<std::size_t>(goal)] = 0.0F;
  open.emplace(0.0F, goal);
  while (!open.empty()) {
    const auto [d, point] = open.top();
    open.pop();
    if (d > field[static_cast<std::size_t>(point)]) continue;
    for (const auto& [before, length] : predecessors_[static_cast<std::size_t>(point)]) {
      const float through = d + length;
      if (through < field[static_cast<std::size_t>(before)]) {
        field[static_cast<std::size_t>(before)] = through;
        open.emplace(through, before);
      }
    }
  }
  return field;
}

double RoadDistances::travel(const geometry::Pose2& from, const geometry::Pose2& to) {
  const int start = nearest_.nearest_point(from.position(), RoadPlanner::PointUse::kRoute);
  const int goal = nearest_.nearest_point(to.position(), RoadPlanner::PointUse::kRoute);
  if (start < 0 || goal < 0) return std::numeric_limits<double>::infinity();
  const float along = to_point(goal)[static_cast<std::size_t>(start)];
  if (!std::isfinite(along)) return std::numeric_limits<double>::infinity();
  return geometry::distance(from.position(), nearest_.point(start)) + static_cast<double>(along);
}

}  // namespace fleet::planning
