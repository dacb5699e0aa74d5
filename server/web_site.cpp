#include <algorithm>
#include <nlohmann/json.hpp>

#include "server/web_json.hpp"
#include "server/web_server.hpp"
#include "sim/tricycle.hpp"
#include "vehicle/factsheet.hpp"

// What the page draws that never changes while the server runs (GET /api/site) and the fleets'
// factsheets (GET /api/fleets).

namespace fleet::server {

using nlohmann::json;
using namespace web_json;

namespace {

/// A stacker's two fork tines, body frame: the simulated stacker's (sim::TricycleGeometry) with
/// their tips at the footprint's back end, where its software puts them
/// (robot::StackerConfig::for_vehicle). Empty for the robot types without forks.
json forks_json(const config::FleetSpec& fleet) {
  json forks = json::array();
  if (fleet.robot_type != "stacker" || fleet.profile.footprint.empty()) return forks;
  const auto& footprint = fleet.profile.footprint;
  const double back = std::min_element(footprint.begin(), footprint.end(), [](auto a, auto b) { return a.x < b.x; })->x;
  const sim::TricycleGeometry geometry;
  for (const auto& tine : sim::tricycle_forks(geometry)) {
    json polygon = json::array();
    for (const auto& p : tine) polygon.push_back(point(p.x - geometry.fork_tip_x() + back, p.y));
    forks.push_back(std::move(polygon));
  }
  return forks;
}

}  // namespace

json fleets_json(const config::FleetConfig& config) {
  json fleets = json::array();
  for (const auto& fleet : config.fleets) {
    std::vector<std::string> robot_ids;
    for (const auto& robot : fleet.robots) robot_ids.push_back(robot.id);
    fleets.push_back(vehicle::factsheet(fleet.id, fleet.robot_type, fleet.profile, robot_ids));
  }
  return json{{"fleets", std::move(fleets)}};
}

json site_json(const WebSiteInfo& info) {
  const map::SiteMap& sm = *info.site_map;
  const map::Site& site = sm.site;
  json j;
  j["site"] = site.name;
  j["bounds"] = {{"min_x", site.bounds.min_x},
                 {"min_y", site.bounds.min_y},
                 {"max_x", site.bounds.max_x},
                 {"max_y", site.bounds.max_y}};
  j["road_width"] = site.road_width;
  j["pallet_size"] = 0.4 * site.road_width;  // as drawn by map::render_svg

  // Lanes as outlines between their borders, exact for any width profile, and the reference
  // lines; sampled as map::render_svg does, at half the graph spacing.
  const double step = std::max(site.graph_spacing * 0.5, 1e-3);
  json lanes = json::array();
  json references = json::array();
  for (const map::Road& road : sm.network.roads) {
    for (std::size_t si = 0; si < road.sections.size(); ++si) {
      const double s0 = road.sections[si].s;
      const double s1 = road.section_end(si);
      const int n = std::clamp(static_cast<int>(std::ceil((s1 - s0) / step)), 1, 4000);
      for (const auto* side : {&road.sections[si].left, &road.sections[si].right}) {
        for (const map::Lane& lane : *side) {
          json inner = json::array();
          json outer = json::array();
          double width_sum = 0.0;
          for (int i = 0; i <= n; ++i) {
            const double s = s0 + (s1 - s0) * i / n;
            const map::RefPoint ref = map::evaluate_reference(road, s);
            const double t = map::lane_center_t(road, si, lane.id, s);
            const double width = map::lane_width_at(road, si, lane.id, s);
            width_sum += width;
            const double nx = -std::sin(ref.hdg), ny = std::cos(ref.hdg);
            inner.push_back(point(ref.x + (t - width / 2) * nx, ref.y + (t - width / 2) * ny));
            outer.push_back(point(ref.x + (t + width / 2) * nx, ref.y + (t + width / 2) * ny));
          }
          json outline = std::move(inner);
          for (auto it = outer.rbegin(); it != outer.rend(); ++it) outline.push_back(*it);
          lanes.push_back({{"road", road.id},
                           {"lane", lane.id},
                           {"drivable", lane.drivable()},
                           {"width", r3(width_sum / (n + 1))},
                           {"outline", std::move(outline)}});
        }
      }
    }
    const int n = std::clamp(static_cast<int>(std::ceil(road.length / step)), 1, 8000);
    json line = json::array();
    for (int i = 0; i <= n; ++i) {
      const map::RefPoint p = map::evaluate_reference(road, road.length * i / n);
      line.push_back(point(p.x, p.y));
    }
    references.push_back({{"road", road.id}, {"points", std::move(line)}});
  }
  j["lanes"] = std::move(lanes);
  j["references"] = std::move(references);

  const map::RoadGraph& graph = sm.graph.graph;
  json points = json::array();
  json edges = json::array();
  for (std::size_t i = 0; i < graph.points.size(); ++i) {
    points.push_back(point(graph.points[i].x, graph.points[i].y));
    for (const int k : graph.successors[i]) edges.push_back(json::array({static_cast<int>(i), k}));
  }
  j["graph"] = {{"points", std::move(points)}, {"edges", std::move(edges)}};

  json areas = json::array();
  for (const auto& a : site.loading_areas) {
    json area = pose_json(a.id, a.pose);
    area["pallet_at_start"] = a.pallet_at_start;
    areas.push_back(std::move(area));
  }
  j["areas"] = std::move(areas);
  json obstacles = json::array();
  for (const auto& o : site.static_obstacles) {
    obstacles.push_back({{"id", o.id}, {"polygon", polygon_json(o.polygon)}, {"enabled_at_start", o.enabled_at_start}});
  }
  j["obstacles"] = std::move(obstacles);
  json racks = json::array();
  for (const auto& r : site.racks) racks.push_back({{"id", r.id}, {"polygon", polygon_json(r.polygon)}});
  j["racks"] = std::move(racks);
  json anchors = json::array();
  for (const auto& a : site.uwb_anchors) anchors.push_back({{"id", a.id}, {"x", a.x}, {"y", a.y}, {"z", a.z}});
  j["anchors"] = std::move(anchors);
  json homes = json::array();
  for (const auto& h : site.homes) homes.push_back(pose_json(h.id, h.pose));
  j["homes"] = std::move(homes);

  json robots = json::array();
  json fleets = json::array();
  if (info.config) {
    for (const auto& [fleet, robot] : info.config->all_robots()) {
      json polygon = json::array();
      for (const auto& p : fleet->profile.footprint) polygon.push_back({p.x, p.y});
      json spec = {{"id", robot->id},
                   {"fleet", fleet->id},
                   {"type", fleet->robot_type},
                   {"home", robot->home},
                   {"fp", json::array({fleet->footprint.length, fleet->footprint.width})},
                   {"poly", std::move(polygon)}};
      if (json forks = forks_json(*fleet); !forks.empty()) spec["forks"] = std::move(forks);
      // A vehicle of another maker, driven over VDA 5050: its maker and serial number.
      if (fleet->vda5050) spec["vda5050"] = fleet->vda5050->manufacturer + " " + robot->serial_number;
      robots.push_back(std::move(spec));
    }
    for (const auto& fleet : info.config->fleets) fleets.push_back({{"id", fleet.id}, {"type", fleet.robot_type}});
  }
  j["robots"] = std::move(robots);
  j["fleets"] = std::move(fleets);
  j["maps"] = info.maps;
  return j;
}

}  // namespace fleet::server
