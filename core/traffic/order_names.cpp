#include "traffic/order_names.hpp"

#include "traffic/traffic_settings.hpp"

namespace fleet::traffic {

orders::KnownNames order_request_names(const config::FleetConfig& config, const map::SiteMap& site,
                                       const std::map<std::string, map::RoadGraph>& fleet_graphs) {
  orders::KnownNames names = orders::known_names(config, site.site);
  for (auto& ability : names.abilities) {
    ability.out_of_reach = fleet_places_out_of_reach(site, fleet_graphs.at(ability.fleet_id), config, ability.fleet_id);
  }
  return names;
}

orders::KnownNames order_request_names(const config::FleetConfig& config, const map::SiteMap& site) {
  return order_request_names(config, site, fleet_graphs(site.graph.graph, config));
}

}  // namespace fleet::traffic
