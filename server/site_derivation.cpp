#include "server/site_derivation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "traffic/order_names.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::server {

SiteDerivation derive_site(std::shared_ptr<const map::SiteMap> site_map, const config::FleetConfig& config) {
  SiteDerivation d;
  const auto graphs = traffic::fleet_graphs(site_map->graph.graph, config);
  d.known_names = std::make_shared<const orders::KnownNames>(traffic::order_request_names(config, *site_map, graphs));
  for (const auto& [fleet_id, graph] : graphs) d.travel.emplace(fleet_id, planning::RoadDistances(graph));
  if (config.settings.get_bool("traffic.enabled")) {
    if (config.settings.get_string("traffic.core") == "places") {
      d.places = std::make_unique<PlaceTrafficSite>(site_map, config);
    } else {
      d.traffic = std::make_unique<traffic::TrafficManager>(site_map->graph.graph, traffic::configuration_from(config));
    }
  }
  d.site_map = std::move(site_map);
  return d;
}

SiteDerivation load_revision(const map::Site& current, const std::string& map_id, const config::FleetConfig& config) {
  std::shared_ptr<const map::SiteMap> next;
  try {
    next = std::make_shared<const map::SiteMap>(
        map::load_site_map((std::filesystem::path(current.file).parent_path() / (map_id + ".yaml")).string()));
  } catch (const std::exception& e) {
    throw std::runtime_error("map '" + map_id + "' cannot be loaded: " + e.what());
  }
  if (std::string why = map::revision_mismatch(current, next->site); !why.empty()) throw std::runtime_error(why);
  return derive_site(std::move(next), config);
}

std::string robot_on_closed_road(const map::SiteMap& current, const map::SiteMap& next, const std::string& map_id,
                                 const std::map<std::string, geometry::Vec2>& standing) {
  // Refused, as an obstacle over a robot is: the robot would wait there until the map was
  // switched back.
  constexpr double kOnRoadM = 0.15;     // half a lane: the robot stands on that road
  constexpr double kSamePointM = 0.02;  // a point the new graph has too
  const auto& old_points = current.graph.graph.points;
  const auto& new_points = next.graph.graph.points;
  for (const auto& [id, at] : standing) {
    for (const auto& p : old_points) {
      if (geometry::distance(at, {p.x, p.y}) > kOnRoadM) continue;
      const bool kept = std::any_of(new_points.begin(), new_points.end(), [&](const auto& q) {
        return geometry::distance({p.x, p.y}, {q.x, q.y}) <= kSamePointM;
      });
      if (!kept) {
        return fmt::format("robot {} stands at ({:.2f}, {:.2f}) on a road map '{}' closes: switch once it has left", id,
                           at.x, at.y, map_id);
      }
    }
  }
  return "";
}

}  // namespace fleet::server
