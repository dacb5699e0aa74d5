#pragma once

#include <map>
#include <memory>
#include <string>

#include "config/fleet_config.hpp"
#include "geometry/pose.hpp"
#include "map/site_map.hpp"
#include "orders/order_request_check.hpp"
#include "planning/road_travel.hpp"
#include "server/place_traffic_control.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::server {

/// What the server derives from a site map: the names orders may use with what each fleet can
/// reach, each fleet's road distances, and the traffic core with the site's conflict zones.
/// On the plant it takes the best part of a second, so a map switch derives it off the server
/// loop and adopts it on the loop once it is ready.
struct SiteDerivation {
  std::shared_ptr<const map::SiteMap> site_map;
  /// Shared with the web API, which checks orders against the same names.
  std::shared_ptr<const orders::KnownNames> known_names;
  std::map<std::string, planning::RoadDistances> travel;
  /// The traffic manager (`traffic.core: manager`); null when traffic.enabled is false.
  std::unique_ptr<traffic::TrafficManager> traffic;
  /// The coordination core (`traffic.core: places`); null unless traffic is on with that core.
  std::unique_ptr<PlaceTrafficSite> places;
};

/// Derives `site_map` for the fleets of `config`.
SiteDerivation derive_site(std::shared_ptr<const map::SiteMap> site_map, const config::FleetConfig& config);

/// Loads map `map_id` from the folder of `current`'s file, checks that it is a revision of the
/// same site (map::revision_mismatch) and derives it. Throws std::runtime_error with the reason
/// for the operator.
SiteDerivation load_revision(const map::Site& current, const std::string& map_id, const config::FleetConfig& config);

/// Why robots may not be switched from `current` onto map `map_id` (`next`) now: a robot of
/// `standing` (robot id -> where it stands) is on a road `next` closes, where it would be off its
/// graph with no way back onto it. Empty when none is.
std::string robot_on_closed_road(const map::SiteMap& current, const map::SiteMap& next, const std::string& map_id,
                                 const std::map<std::string, geometry::Vec2>& standing);

}  // namespace fleet::server
