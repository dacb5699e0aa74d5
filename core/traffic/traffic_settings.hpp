#pragma once

#include <map>
#include <string>

#include "config/fleet_config.hpp"
#include "map/road_graph.hpp"
#include "map/site_map.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {

/// The footprint of a fleet's vehicles in the body frame, for traffic: today the fleet's
/// length x width rectangle centred on the body origin.
geometry::Polygon footprint_polygon_of(const config::FleetSpec& fleet);

/// The traffic configuration of a run, from the `traffic.*` keys and the fleets: one vehicle
/// type per fleet, in the order of `config.fleets` (vehicle_type_of gives a fleet's index). The
/// server's manager and every agent build it from the same config, so agents plan on the very
/// graph the manager grants on.
TrafficConfiguration configuration_from(const config::FleetConfig& config);

/// The gap traffic keeps between the bodies of robots at conflicting places: `traffic.places_margin`
/// under the coordination core (`traffic.core: places`), else `traffic.margin`. The agents' look
/// ahead keeps half of it.
double reservation_margin(const config::FleetConfig& config);

/// Whether corridors on cycles are driven one way: `traffic.places_one_way` under the coordination
/// core, else `traffic.one_way`.
bool one_way_lanes(const config::FleetConfig& config);

/// The vehicle type index of fleet `fleet_id` under configuration_from(config); 0 when unknown.
int vehicle_type_of(const config::FleetConfig& config, const std::string& fleet_id);

/// The graph traffic control lets robots drive under `configuration`: with `one_way` set, the
/// one-way plan's (the corridors on cycles of the road network driven one way), else `graph`.
map::RoadGraph driving_graph(const map::RoadGraph& graph, const TrafficConfiguration& configuration);

/// The graph robots of vehicle type `type` plan their routes on under `configuration`: the
/// one-way graph when `one_way` is set, else `graph` itself, with only the lanes the type fits.
/// Deterministic: equal to TrafficManager::route_graph(type).
map::RoadGraph planning_graph(const map::RoadGraph& graph, const TrafficConfiguration& configuration, int type = 0);

/// The graph each fleet's robots plan on, by fleet id: its vehicle type's planning graph under
/// traffic control (equal to planning_graph for its type), else the site's graph with only the
/// lanes its vehicle fits. The conflict zones and the one-way plan are computed once for all.
std::map<std::string, map::RoadGraph> fleet_graphs(const map::RoadGraph& graph, const config::FleetConfig& config);

/// The places (loading areas and homes) of `site` a fleet's robots cannot reach on `fleet_graph`:
/// the graph point in front of the place (where the vehicle handles it) has no way in.
/// With `handling_road_width` > 0 also the loading areas whose road in front is narrower (every
/// lane of that road at that point, added up): the robot type turns there to handle the load.
std::vector<std::string> places_out_of_reach(const map::SiteMap& site, const map::RoadGraph& fleet_graph,
                                             double handling_road_width = 0.0);
/// places_out_of_reach for fleet `fleet_id` of `config`, with its robot type's handling road width.
std::vector<std::string> fleet_places_out_of_reach(const map::SiteMap& site, const map::RoadGraph& fleet_graph,
                                                   const config::FleetConfig& config, const std::string& fleet_id);

}  // namespace fleet::traffic
