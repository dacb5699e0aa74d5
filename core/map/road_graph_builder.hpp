#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "map/opendrive.hpp"
#include "map/road_graph.hpp"

namespace fleet::map {

/// How the road graph is sampled [Forklift thesis, section 5.1].
struct GraphOptions {
  double spacing = 0.10;  ///< metres between samples along a lane; the site file's graph_spacing
  /// The seed's table has single-lane roads a forklift drives both ways. When true, a road with
  /// exactly one drivable lane in every section is driven both ways whatever its side; when
  /// false, lanes follow the traffic rule (RHT: right lanes along s, left lanes against it).
  bool single_lane_roads_both_ways = true;
  /// Lane width, metres, of points whose lane has no <width> record; the site file's road_width.
  double default_lane_width = 0.0;
};

/// Which way traffic may move along a lane, relative to increasing s.
enum class LaneDirection { kForward, kBackward, kBoth };

/// The samples of one drivable lane of one lane section, in increasing s.
struct GraphLane {
  std::size_t road = 0;     ///< index into RoadNetwork::roads
  std::size_t section = 0;  ///< index into Road::sections
  int lane_id = 0;
  LaneDirection direction = LaneDirection::kForward;
  std::vector<int> points;  ///< graph point ids, s ascending
};

struct RoadGraphBuild {
  RoadGraph graph;
  std::vector<GraphLane> lanes;
};

/// Samples the centre of every drivable lane and connects the samples along each lane, across
/// lane sections, across road links (honouring contactPoint) and through junction connections
/// (honouring laneLinks), in the lanes' driving directions [Forklift thesis, section 5.1, Fig. 5.3].
/// Throws MapError when spacing is not positive.
RoadGraphBuild build_road_graph_detailed(const RoadNetwork& network, const GraphOptions& options);

/// The graph alone.
RoadGraph build_road_graph(const RoadNetwork& network, const GraphOptions& options);

// ---- analysis ---------------------------------------------------------------------------------

/// Component index of every point, ignoring edge direction; returns the component count.
std::size_t weak_components(const RoadGraph& graph, std::vector<int>& component);

/// Strongly connected components (Tarjan, iterative); returns the component count.
std::size_t strong_components(const RoadGraph& graph, std::vector<int>& component);

/// Id of the point nearest (x, y), -1 for an empty graph; `distance` receives the distance.
int nearest_point(const RoadGraph& graph, double x, double y, double* distance = nullptr);

/// Distance from (x, y) to the nearest edge segment (or point when there are no edges).
double distance_to_graph(const RoadGraph& graph, double x, double y);

}  // namespace fleet::map
