#pragma once

#include "config/fleet_config.hpp"
#include "map/road_graph.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {

/// The traffic configuration of a run, from the `traffic.*` keys and the fleets' footprints
/// (resources are sized by the largest robot). The server's manager and every agent build it
/// from the same config, so agents plan on the very graph the manager grants on.
TrafficConfiguration configuration_from(const config::FleetConfig& config);

/// The graph robots plan their routes on under `configuration`: the one-way graph when
/// `one_way` is set, else `graph` itself. Deterministic: equal to TrafficManager::route_graph().
map::RoadGraph planning_graph(const map::RoadGraph& graph, const TrafficConfiguration& configuration);

}  // namespace fleet::traffic
