#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::traffic {

/// Shortest routes on the road graph (Dijkstra on edge length) that keep out of given places.
/// The traffic manager uses it for re-routes and sidings; the simulator plans trips with it.
/// Buffers are reused between queries: one query at a time per instance.
class RouteSearch {
 public:
  RouteSearch(const map::RoadGraph& graph, const ConflictZones& zones);

  /// Shortest route of point ids from `from` to any point of `to`'s place, entering no place with
  /// blocked[place] != 0 (the start place is always allowed). Empty when there is none.
  std::vector<int> shortest(int from, int to, const std::vector<std::uint8_t>* blocked = nullptr);

  /// Shortest route from `from` to the nearest point whose place satisfies `accept` (the start
  /// place excluded), through unblocked places. Empty when there is none.
  std::vector<int> nearest(int from, const std::function<bool(int place)>& accept, const std::vector<std::uint8_t>* blocked);

  /// Metres along a route of point ids.
  double length(const std::vector<int>& route) const;
  double edge_length(int a, int b) const;

 private:
  std::vector<int> search(int from, const std::function<bool(int point)>& is_goal, const std::vector<std::uint8_t>* blocked);

  const ConflictZones& zones_;
  std::vector<double> xs_, ys_;
  std::vector<std::vector<int>> successors_;
  std::vector<double> dist_;
  std::vector<int> parent_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t query_ = 0;
};

}  // namespace fleet::traffic
