#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fleet::map {

/// A point sampled on the centre line of a driving lane [Forklift thesis, section 5.1, Fig. 5.3-5.5].
struct GraphPoint {
  int id = 0;  ///< index into RoadGraph::points, unique within the graph
  double x = 0.0;
  double y = 0.0;
  std::string road_id;
  int lane_id = 0;
  double s = 0.0;  ///< position along the road's reference line, metres
  /// Width of the lane at this point, metres: the OpenDRIVE lane width, else the site's
  /// `road_width`; 0 when unknown (a graph built in code), which every vehicle fits.
  double lane_width = 0.0;
};

/// The road graph planners search: directed edges between points, consecutive along a lane and
/// across road links and junction connections. A lane driven both ways has edges both ways.
struct RoadGraph {
  std::vector<GraphPoint> points;
  std::vector<std::vector<int>> successors;  ///< successors[i]: ids reachable from point i in one step

  std::size_t edge_count() const {
    std::size_t n = 0;
    for (const auto& s : successors) n += s.size();
    return n;
  }
};

}  // namespace fleet::map
