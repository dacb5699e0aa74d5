#pragma once

#include "map/road_graph.hpp"

namespace fleet::traffic {

/// Whether a vehicle `footprint_width` wide, keeping `margin` to the lane's edges in all, fits a
/// lane `lane_width` wide. A lane of unknown width (0) fits every vehicle.
bool fits_lane(double lane_width, double footprint_width, double margin);

/// `graph` with only the lanes a vehicle `footprint_width` wide fits (fits_lane): every edge into
/// a point of a too-narrow lane is removed. Point ids stay those of `graph`, so routes and places
/// are shared by every vehicle type's graph; a vehicle standing in a narrow lane may still leave it.
map::RoadGraph lane_graph_for(const map::RoadGraph& graph, double footprint_width, double margin);

}  // namespace fleet::traffic
