#include "traffic/vehicle_lanes.hpp"

#include <algorithm>

namespace fleet::traffic {

bool fits_lane(double lane_width, double footprint_width, double margin) {
  return !(lane_width > 0.0) || lane_width >= footprint_width + margin;
}

map::RoadGraph lane_graph_for(const map::RoadGraph& graph, double footprint_width, double margin) {
  map::RoadGraph out = graph;
  for (auto& next : out.successors) {
    next.erase(std::remove_if(next.begin(), next.end(),
                              [&](int j) {
                                return !fits_lane(graph.points[static_cast<std::size_t>(j)].lane_width, footprint_width,
                                                  margin);
                              }),
               next.end());
  }
  return out;
}

}  // namespace fleet::traffic
