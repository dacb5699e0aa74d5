#pragma once
// The site's state beyond its orders, as one record: what stands where (the load ledger), the
// parking place each robot goes home to, and which static obstacles are on, with the map they
// belong to. A server stores it whole after every change and reads it back after a restart; it is
// what a standby mirrors besides the orders.

#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "config/fleet_config.hpp"
#include "map/site.hpp"
#include "orders/area_ledger.hpp"

namespace fleet::orders {

struct SiteState {
  std::string map_id;                            ///< the map the obstacles belong to
  AreaLedger ledger;                             ///< the loads, and the places that hold one
  std::map<std::string, std::string> parked_at;  ///< robot -> the parking place it goes home to
  std::map<std::string, bool> obstacle_enabled;  ///< obstacle id -> on
};

/// The state as one JSON document (version 1): `map`, `loads` (id, kind, x, y, yaw, place,
/// carried_by), `held_unnamed` (places that hold a load no record names), `parked_at` and
/// `obstacles` (id -> on). Keys and arrays come in a fixed order, so one state gives one text.
std::string to_json(const SiteState& state);

/// What the site served now has, to read a stored state against.
struct SiteNames {
  std::string map_id;
  std::vector<Place> places;        ///< the loading areas in the site's order
  std::set<std::string> robots;     ///< the configured robots
  std::set<std::string> obstacles;  ///< the static obstacles of `map_id`
};

/// The names of `site` (its loading areas as places, its static obstacles) with the robots of
/// `config`.
SiteNames site_names_of(const map::Site& site, const config::FleetConfig& config);

/// A stored state read back, and what it named that the site no longer has: each such entry is
/// left out and said in one sentence, for the log.
struct RestoredSiteState {
  SiteState state;
  std::vector<std::string> dropped;
};

/// Reads a state written by to_json against the site as it is now; what it holds overrides the
/// site file's start (robots and obstacles it does not name keep theirs). A load on a place the site no
/// longer has keeps its pose and stands on no place; parking places and obstacles of robots,
/// places or obstacles the site lacks are left out; obstacles stored for another map than
/// `site.map_id` are all left out (they start as the site file sets them). Throws InputError naming
/// `source` and the key when the text is not such a document.
RestoredSiteState site_state_from_json(std::string_view text, const SiteNames& site, const std::string& source);

}  // namespace fleet::orders
