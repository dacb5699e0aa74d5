#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <queue>
#include <unordered_map>
#include <utility>
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
  /// cannot get there. One search backwards from each type and goal answers every place: it goes
  /// only as far as the places asked for so far, and goes on when asked for one beyond.
  double distance(int type, int place, int goal);
  /// Searches kept at most (the least recently asked goes first): a goal's takes about 8 bytes a
  /// place.
  static constexpr std::size_t kMaxGoalSearches = 1024;
  /// Places the searches have settled since the graph was made (a measure of their work).
  std::uint64_t places_settled() const { return places_settled_; }

 private:
  /// Reverse Resumable A* [Silver 2005, "Hierarchical Cooperative A*"]: A* backwards from the goal towards the place
  /// first asked for, its heuristic the straight line to that place. The heuristic is consistent
  /// (a move is as long as the straight line between its places), so every settled place's
  /// metres are exact, whichever place the search went on for.
  struct GoalSearch {
    using Entry = std::pair<double, int>;  ///< metres to the goal + straight line, place
    geometry::Vec2 towards;
    std::vector<double> metres;  ///< by place: the best known way to the goal
    std::vector<bool> settled;   ///< by place: `metres` is exact
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
    std::uint64_t last_asked = 0;
  };
  GoalSearch& search_for(int type, int place, int goal);
  /// Settles places until `place` is, or nothing is left to settle.
  void settle(GoalSearch& search, int type, int place);

  const traffic::ConflictZones& zones_;
  std::vector<std::vector<std::vector<int>>> successors_;    ///< by type, by place
  std::vector<std::vector<std::vector<int>>> predecessors_;  ///< by type, by place
  std::unordered_map<std::int64_t, GoalSearch> searches_;
  std::uint64_t asked_ = 0;
  std::uint64_t places_settled_ = 0;
};

}  // namespace fleet::coordination
