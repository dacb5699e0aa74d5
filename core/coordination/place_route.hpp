#pragma once

#include <cstddef>
#include <vector>

#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

/// A route a robot drives as PlaceTraffic follows it: its road graph points, the metres along it
/// at each, and the places it passes (consecutive points of one place merged).
struct PlaceRoute {
  std::vector<int> points;
  std::vector<double> point_s;   ///< metres along the route at each point
  std::vector<int> places;       ///< the route's places, consecutive repeats merged
  std::vector<int> place_point;  ///< per entry of `places`: the index of its last point

  /// Takes `route` (points of `graph`), its places those of `zones`.
  void assign(const map::RoadGraph& graph, const traffic::ConflictZones& zones, const std::vector<int>& route);
  /// The index into `places` of the place the body is in `progress` metres along the route: past
  /// the midpoint of a move the body is inside the place it drives to.
  int index_at(double progress) const;
  /// Metres along the route to its `index`-th place.
  double place_s(std::size_t index) const { return point_s[static_cast<std::size_t>(place_point[index])]; }
  /// The places from index `from` on, as far as `length` metres beyond it.
  std::vector<int> places_within(std::size_t from, double length) const;
  /// The index of the end of the route's leg after index `from` (< the last): the first place at
  /// which the route turns back on itself, or its end.
  std::size_t leg_end(std::size_t from) const;
};

}  // namespace fleet::coordination
