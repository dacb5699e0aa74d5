#pragma once

#include <map>
#include <string>

#include "config/fleet_config.hpp"
#include "map/road_graph.hpp"
#include "map/site_map.hpp"
#include "orders/order_request_check.hpp"

namespace fleet::traffic {

/// The names an order request is checked against (orders::check_order_request), built once from
/// the site and the configuration: the site's places and homes, the robots, the fleets with the
/// actions they offer, and for each fleet the places its vehicles cannot reach on the roads they
/// fit (fleet_places_out_of_reach on `fleet_graphs`, see fleet_graphs). The server, the web API
/// and fleetctl check orders against the same names.
orders::KnownNames order_request_names(const config::FleetConfig& config, const map::SiteMap& site,
                                       const std::map<std::string, map::RoadGraph>& fleet_graphs);
/// The same, with the fleets' graphs made here (the site's conflict zones: most of a second on
/// the plant).
orders::KnownNames order_request_names(const config::FleetConfig& config, const map::SiteMap& site);

}  // namespace fleet::traffic
