#pragma once

#include <vector>

#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::traffic {

/// A one-way traffic plan for a road graph: every corridor between two junctions that does not
/// disconnect the network gets one driving direction, chosen so that every place stays reachable
/// from every other (Robbins 1939: a connected graph without bridges has a strongly connected
/// orientation; orient a depth-first tree away from the root and every other edge back towards
/// it). Corridors that are bridges (dead ends, the only link to a part of the site) and the short
/// connecting corridors inside junction zones stay two-way, so no turn is lost.
///
/// Robots that plan on the one-way graph never meet head-on in a one-way corridor; head-on
/// meetings, the costliest case on single-lane roads, are left to the dead ends. Lanes the graph
/// already drives one way only (the two lanes of a two-way road, keep right) are not oriented
/// again: they keep their direction and their edges, and link the parts of the site they join.
struct OneWayPlan {
  map::RoadGraph graph;                 ///< the input graph without the edges against a corridor's direction
  std::vector<int> corridor_direction;  ///< per corridor: +1 / -1 along corridor_index, 0 two-way (lanes directed by
                                        ///< the graph: their direction)
};

OneWayPlan one_way_plan(const map::RoadGraph& graph, const ConflictZones& zones);

}  // namespace fleet::traffic
