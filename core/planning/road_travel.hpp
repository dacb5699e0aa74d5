#pragma once
// How far a vehicle drives on the road graph between two poses, for whoever estimates travel
// without driving it (dispatch costs, cycle-time evaluations).

#include <unordered_map>
#include <vector>

#include "geometry/pose.hpp"
#include "map/road_graph.hpp"
#include "planning/road_planner.hpp"

namespace fleet::planning {

/// Metres driven from `from` to `to` on `planner`'s graph: from `from` onto the route's first
/// point, the route [Forklift thesis, section 5.2], and from its last point to `to`; +infinity
/// when the planner finds no route.
double road_travel_distance(RoadPlanner& planner, const geometry::Pose2& from, const geometry::Pose2& to);

/// Metres to one place from every point of a road graph at once: Dijkstra from the goal over the
/// reversed edges. Dispatch asks how far each of hundreds of free robots is from an order's pick
/// place; one search answers for all of them, where a route search per robot would not keep up.
/// The fields of the places asked for are kept (up to kKeptGoals, then all are dropped).
class RoadDistances {
 public:
  explicit RoadDistances(const map::RoadGraph& graph);

  /// Metres driven from `from` to the graph point nearest `to`: onto the graph point nearest
  /// `from`, then the shortest way along the edges; +infinity when there is none. Like
  /// road_travel_distance without the last leg off the graph, by length alone (no heading cost).
  double travel(const geometry::Pose2& from, const geometry::Pose2& to);
  /// Metres from every point to point `goal` (+infinity where it cannot be reached).
  const std::vector<float>& to_point(int goal);

  static constexpr std::size_t kKeptGoals = 256;

 private:
  RoadPlanner nearest_;                                           ///< the graph's points, for the nearest one to a pose
  std::vector<std::vector<std::pair<int, float>>> predecessors_;  ///< reversed edges with their lengths
  std::unordered_map<int, std::vector<float>> fields_;
};

}  // namespace fleet::planning
