#include "orders/site_state.hpp"

#include <cmath>
#include <nlohmann/json.hpp>

#include "common/errors.hpp"

namespace fleet::orders {

namespace {

constexpr int kVersion = 1;

using nlohmann::json;

/// Reads one document, each failure naming the source and the key.
class Reader {
 public:
  explicit Reader(const std::string& source) : source_(source) {}

  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(source_ + ": site state: " + where + ": " + what);
  }
  const json& member(const json& object, const char* key, const std::string& where) const {
    const auto it = object.find(key);
    if (it == object.end()) fail(where, std::string("missing key '") + key + "'");
    return *it;
  }
  std::string text(const json& object, const char* key, const std::string& where) const {
    const json& v = member(object, key, where);
    if (!v.is_string()) fail(where + "." + key, "not a string: " + v.dump());
    return v.get<std::string>();
  }
  double number(const json& object, const char* key, const std::string& where) const {
    const json& v = member(object, key, where);
    if (!v.is_number() || !std::isfinite(v.get<double>())) fail(where + "." + key, "not a finite number: " + v.dump());
    return v.get<double>();
  }
  const json& of_type(const json& object, const char* key, const std::string& where, json::value_t type,
                      const char* type_name) const {
    const json& v = member(object, key, where);
    if (v.type() != type) fail(where + "." + key, std::string("not ") + type_name + ": " + v.dump());
    return v;
  }

 private:
  const std::string& source_;
};

Load read_load(const Reader& read, const json& item, const std::string& where) {
  if (!item.is_object()) read.fail(where, "not an object: " + item.dump());
  Load load;
  const double id = read.number(item, "id", where);
  if (id != std::floor(id) || id < 0 || id > 2.0e9) read.fail(where + ".id", "not a load id: " + item["id"].dump());
  load.id = static_cast<int>(id);
  load.kind = read.text(item, "kind", where);
  load.pose = {read.number(item, "x", where), read.number(item, "y", where), read.number(item, "yaw", where)};
  load.place = read.text(item, "place", where);
  load.carried_by = read.text(item, "carried_by", where);
  return load;
}

bool has_place(const SiteNames& site, const std::string& id) {
  for (const Place& p : site.places) {
    if (p.id == id) return true;
  }
  return false;
}

}  // namespace

std::string to_json(const SiteState& state) {
  json loads = json::array();
  for (const auto& [id, load] : state.ledger.loads()) {
    loads.push_back({{"id", load.id},
                     {"kind", load.kind},
                     {"x", load.pose.x},
                     {"y", load.pose.y},
                     {"yaw", load.pose.yaw},
                     {"place", load.place},
                     {"carried_by", load.carried_by}});
  }
  json held = json::array();
  for (const auto& [place, holds] : state.ledger.occupancy()) {
    if (holds && !state.ledger.standing_on(place)) held.push_back(place);
  }
  json doc = {{"version", kVersion},          {"map", state.map_id},
              {"loads", std::move(loads)},    {"held_unnamed", std::move(held)},
              {"parked_at", state.parked_at}, {"obstacles", state.obstacle_enabled}};
  return doc.dump();
}

RestoredSiteState site_state_from_json(std::string_view text, const SiteNames& site, const std::string& source) {
  const Reader read(source);
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::parse_error& e) {
    read.fail("document", std::string("not JSON: ") + e.what());
  }
  if (!doc.is_object()) read.fail("document", "not a JSON object");
  if (const double version = read.number(doc, "version", "document"); version != kVersion) {
    read.fail("version",
              "version " + doc["version"].dump() + " is not the " + std::to_string(kVersion) + " this server reads");
  }
  RestoredSiteState out;
  out.state.map_id = site.map_id;
  out.state.ledger = AreaLedger(site.places);
  for (const json& item : read.of_type(doc, "loads", "document", json::value_t::array, "an array")) {
    Load load = read_load(read, item, "loads[" + std::to_string(out.state.ledger.loads().size()) + "]");
    if (!load.place.empty() && !has_place(site, load.place)) {
      out.dropped.push_back("load " + std::to_string(load.id) + " stood on '" + load.place +
                            "', which the site no longer has: it is kept where it stood, on no place");
      load.place.clear();
    }
    out.state.ledger.record(std::move(load));
  }
  for (const json& place : read.of_type(doc, "held_unnamed", "document", json::value_t::array, "an array")) {
    if (!place.is_string()) read.fail("held_unnamed", "not a place id: " + place.dump());
    if (has_place(site, place.get<std::string>())) {
      out.state.ledger.record_unnamed_drop(place.get<std::string>());
    } else {
      out.dropped.push_back("place '" + place.get<std::string>() + "' held a load, but the site no longer has it");
    }
  }
  for (const auto& [robot, place] :
       read.of_type(doc, "parked_at", "document", json::value_t::object, "an object").items()) {
    if (!place.is_string()) read.fail("parked_at." + robot, "not a place id: " + place.dump());
    if (!site.robots.count(robot)) {
      out.dropped.push_back("robot '" + robot + "' parked at '" + place.get<std::string>() + "' is not configured");
    } else {
      out.state.parked_at[robot] = place.get<std::string>();
    }
  }
  const std::string stored_map = read.text(doc, "map", "document");
  const json& obstacles = read.of_type(doc, "obstacles", "document", json::value_t::object, "an object");
  for (const auto& [id, on] : obstacles.items()) {
    if (!on.is_boolean()) read.fail("obstacles." + id, "not true or false: " + on.dump());
    if (stored_map != site.map_id) continue;
    if (!site.obstacles.count(id)) {
      out.dropped.push_back("obstacle '" + id + "' of map '" + stored_map + "' is no longer on the site");
    } else {
      out.state.obstacle_enabled[id] = on.get<bool>();
    }
  }
  if (stored_map != site.map_id && !obstacles.empty()) {
    out.dropped.push_back("the obstacles were stored for map '" + stored_map + "'; on map '" + site.map_id +
                          "' they start as the site file sets them");
  }
  return out;
}

SiteNames site_names_of(const map::Site& site, const config::FleetConfig& config) {
  SiteNames names{site.name, {}, {}, {}};
  for (const auto& [fleet, robot] : config.all_robots()) names.robots.insert(robot->id);
  for (const auto& area : site.loading_areas) names.places.push_back({area.id, area.pose});
  for (const auto& obstacle : site.static_obstacles) names.obstacles.insert(obstacle.id);
  return names;
}

}  // namespace fleet::orders
