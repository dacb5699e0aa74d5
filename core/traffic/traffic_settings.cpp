#include "traffic/traffic_settings.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "control/tricycle_sweep.hpp"
#include "map/road_graph_builder.hpp"
#include "traffic/one_way.hpp"
#include "traffic/vehicle_lanes.hpp"
#include "vehicle/vehicle_types.hpp"

namespace fleet::traffic {

namespace {

// The lanes and the one-way plan do not depend on what a type sweeps through bends (they are
// made of corridors, stoppable places and footprints), and driving every bend is most of the
// zones' cost.
ResourceParams without_drives(ResourceParams resources) {
  for (VehicleType& type : resources.vehicle_types) type.drive = nullptr;
  return resources;
}

}  // namespace

geometry::Polygon footprint_polygon_of(const config::FleetSpec& fleet) {
  return fleet.profile.footprint;
}

TrafficConfiguration configuration_from(const config::FleetConfig& config) {
  TrafficConfiguration c;
  // The largest footprint stays the one-type fallback for a configuration without fleets.
  c.resources.footprint = {0.0, 0.0};
  for (const auto& fleet : config.fleets) {
    c.resources.footprint.length = std::max(c.resources.footprint.length, fleet.footprint.length);
    c.resources.footprint.width = std::max(c.resources.footprint.width, fleet.footprint.width);
    const int type = static_cast<int>(c.resources.vehicle_types.size());
    const bool tricycle = fleet.profile.kinematics == vehicle::Kinematics::kTricycle;
    VehicleType vehicle{fleet.id, footprint_polygon_of(fleet), tricycle ? fleet.profile.rear_axle_x : 0.0};
    if (tricycle) {
      // Places reserve what the stacker's own pursuit sweeps through the bends, at the speed its
      // agent drives (robot_factory's stacker_config).
      control::TricycleDrive drive = control::tricycle_drive_for(fleet.profile);
      drive.pursuit.max_speed = config.top_speed(fleet);
      // Coarser than the agent's body model (0.005 s): within a millimetre over a bend, and the
      // site's every bend is driven when its places are built.
      drive.body.max_substep = 0.02;
      vehicle.drive = [drive](const std::vector<geometry::Vec2>& path, bool at_speed) {
        return control::drive_along(drive, path, at_speed);
      };
    }
    vehicle.backs_up = !tricycle;
    c.resources.vehicle_types.push_back(std::move(vehicle));
    for (const auto& robot : fleet.robots) c.robot_vehicle_types[robot.id] = type;
  }
  const auto& s = config.settings;
  c.resources.margin = reservation_margin(config);
  c.lookahead = s.get_double("traffic.lookahead");
  c.priority_wait = s.get_double("traffic.priority_wait_s");
  c.reroute_wait = s.get_double("traffic.reroute_wait_s");
  c.lost_reroute_wait = s.get_double("traffic.lost_reroute_wait_s");
  c.one_way = one_way_lanes(config);
  return c;
}

double reservation_margin(const config::FleetConfig& config) {
  const auto& s = config.settings;
  return s.get_string("traffic.core") == "places" ? s.get_double("traffic.places_margin")
                                                  : s.get_double("traffic.margin");
}

bool one_way_lanes(const config::FleetConfig& config) {
  const auto& s = config.settings;
  return s.get_string("traffic.core") == "places" ? s.get_bool("traffic.places_one_way")
                                                  : s.get_bool("traffic.one_way");
}

int vehicle_type_of(const config::FleetConfig& config, const std::string& fleet_id) {
  for (std::size_t i = 0; i < config.fleets.size(); ++i) {
    if (config.fleets[i].id == fleet_id) return static_cast<int>(i);
  }
  return 0;
}

map::RoadGraph planning_graph(const map::RoadGraph& graph, const TrafficConfiguration& configuration, int type) {
  const ConflictZones zones(graph, without_drives(configuration.resources));
  const VehicleType& vehicle = zones.vehicle_types().at(static_cast<std::size_t>(type));
  const double width = footprint_width(vehicle.footprint);
  if (!configuration.one_way) return lane_graph_for(graph, width, configuration.resources.margin);
  return lane_graph_for(one_way_plan(graph, zones).graph, width, configuration.resources.margin);
}

map::RoadGraph driving_graph(const map::RoadGraph& graph, const TrafficConfiguration& configuration) {
  if (!configuration.one_way) return graph;
  return one_way_plan(graph, ConflictZones(graph, without_drives(configuration.resources))).graph;
}

std::map<std::string, map::RoadGraph> fleet_graphs(const map::RoadGraph& graph, const config::FleetConfig& config) {
  TrafficConfiguration configuration = configuration_from(config);
  configuration.one_way = configuration.one_way && config.settings.get_bool("traffic.enabled");
  const map::RoadGraph base = driving_graph(graph, configuration);
  std::map<std::string, map::RoadGraph> graphs;
  for (const auto& fleet : config.fleets) {
    graphs.emplace(fleet.id,
                   lane_graph_for(base, footprint_width(footprint_polygon_of(fleet)), configuration.resources.margin));
  }
  return graphs;
}

namespace {

/// Every lane of the site graph's road at point `p`, added up: the lanes' widths at the points of
/// the same road nearest `p` along it, one per lane.
double road_width_at(const map::RoadGraph& graph, int p) {
  const map::GraphPoint& at = graph.points[static_cast<std::size_t>(p)];
  std::map<int, std::pair<double, double>> lanes;  // lane id -> (|ds|, width)
  for (const map::GraphPoint& q : graph.points) {
    if (q.road_id != at.road_id) continue;
    const double ds = std::abs(q.s - at.s);
    auto [it, added] = lanes.try_emplace(q.lane_id, ds, q.lane_width);
    if (!added && ds < it->second.first) it->second = {ds, q.lane_width};
  }
  double width = 0.0;
  for (const auto& [lane, near] : lanes) width += near.second;
  return width;
}

}  // namespace

std::vector<std::string> fleet_places_out_of_reach(const map::SiteMap& site, const map::RoadGraph& fleet_graph,
                                                   const config::FleetConfig& config, const std::string& fleet_id) {
  double handling = 0.0;
  for (const auto& fleet : config.fleets) {
    if (fleet.id != fleet_id) continue;
    if (const auto* type = vehicle::find_robot_type(fleet.robot_type)) handling = type->handling_road_width;
  }
  return places_out_of_reach(site, fleet_graph, handling);
}

std::vector<std::string> places_out_of_reach(const map::SiteMap& site, const map::RoadGraph& fleet_graph,
                                             double handling_road_width) {
  std::vector<char> has_way_in(fleet_graph.points.size(), 0);
  for (const auto& successors : fleet_graph.successors) {
    for (int next : successors) has_way_in[static_cast<std::size_t>(next)] = 1;
  }
  const auto nearest = [&](double x, double y) { return map::nearest_point(fleet_graph, x, y); };
  std::vector<std::string> out;
  const double approach = site.site.approach_distance;
  for (const auto& area : site.site.loading_areas) {
    const int p =
        nearest(area.pose.x + approach * std::cos(area.pose.yaw), area.pose.y + approach * std::sin(area.pose.yaw));
    if (p < 0 || !has_way_in[static_cast<std::size_t>(p)] ||
        (handling_road_width > 0.0 && road_width_at(site.graph.graph, p) < handling_road_width - 1e-9)) {
      out.push_back(area.id);
    }
  }
  for (const auto& home : site.site.homes) {
    const int p = nearest(home.pose.x, home.pose.y);
    if (p < 0 || !has_way_in[static_cast<std::size_t>(p)]) out.push_back(home.id);
  }
  return out;
}

}  // namespace fleet::traffic
