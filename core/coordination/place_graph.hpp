#pragma once

#include <cstdint>
#include <limits>
#include <unordered_map>
#include <vector>

#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

/// The places of a road site as the coordination core plans over them: the places of
/// traffic::ConflictZones (graph points, road hand-overs merged), each vehicle type's moves
/// between them on the lanes it fits (traffic::lane_graph_for), and the driving distance from
/// any place to a goal place. Which places conflict for which pair of vehicle types is the zones'
/// (their regions overlap); the graph keeps a reference to them.
class PlaceGraph {
 public:
  static constexpr double kUnreachable = std::numeric_limits<double>::infinity();

  PlaceGraph(const map::RoadGraph& graph, const traffic::ConflictZones& zones);

  const traffic::ConflictZones& zones() const { return zones_; }
  int place_count() const { return static_cast<int>(zones_.place_count()); }
  int type_count() const { return static_cast<int>(zones_.type_count()); }
  /// Places a robot of `type` standing at `place` may drive to in one move.
  const std::vector<int>& successors(int type, int place) const {
    return successors_[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)];
  }
  /// Places from which a robot of `type` drives to `place` in one move (where it backs up to).
  const std::vector<int>& predecessors(int type, int place) const {
    return predecessors_[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)];
  }
  /// Metres between two places' positions.
  double step_length(int from, int to) const;
  /// The mean length of a move of vehicle type 0 between neighbouring places, 0 without moves.
  double mean_move_length() const;
  /// Metres a robot of `type` drives from `place` to `goal` on its lanes, kUnreachable when it
  /// cannot get there. Computed once per type and goal (Dijkstra backwards from the goal).
  double distance(int type, int place, int goal);

 private:
  const std::vector<double>& distances_to(int type, int goal);

  const traffic::ConflictZones& zones_;
  std::vector<std::vector<std::vector<int>>> successors_;    ///< by type, by place
  std::vector<std::vector<std::vector<int>>> predecessors_;  ///< by type, by place
  std::unordered_map<std::int64_t, std::vector<double>> distances_;
};

}  // namespace fleet::coordination
