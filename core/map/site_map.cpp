#include "map/site_map.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace fleet::map {

namespace {

std::string fixed(double v, int digits = 2) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

/// Lines of the list entries under `key` in the site file, for messages; empty when unreadable.
std::vector<int> entry_lines(const std::string& path, const std::string& key) {
  std::vector<int> lines;
  try {
    const YAML::Node root = YAML::LoadFile(path);
    const YAML::Node list = root[key];
    if (list && list.IsSequence()) {
      for (const auto& item : list) lines.push_back(item.Mark().line + 1);
    }
  } catch (const YAML::Exception&) {
    // parse_site has already read the file; lines are only decoration here.
  }
  return lines;
}

std::string located(const SiteMap& map, const PlaceReach& place) {
  return map.site.file + (place.line > 0 ? ":" + std::to_string(place.line) : std::string()) + ": key '" + place.key +
         "' (" + place.id + "): ";
}

}  // namespace

SiteMap load_site_map_unchecked(const std::string& path, const GraphOptions& graph_options) {
  SiteMap map;
  map.site = load_site(path);
  if (map.site.opendrive_file.empty()) throw MapError(path + ": key 'opendrive' is missing");
  map.network = load_opendrive(map.site.opendrive_file);
  GraphOptions options = graph_options;
  options.spacing = map.site.graph_spacing;
  if (!(options.default_lane_width > 0.0)) options.default_lane_width = map.site.road_width;
  map.graph = build_road_graph_detailed(map.network, options);
  return map;
}

SiteReport check_site_map(const SiteMap& map, const ReachOptions& options) {
  const RoadGraph& graph = map.graph.graph;
  SiteReport report;
  report.site_file = map.site.file;
  report.opendrive_file = map.site.opendrive_file;
  report.roads = map.network.roads.size();
  report.junctions = map.network.junctions.size();
  report.points = graph.points.size();
  report.edges = graph.edge_count();
  std::vector<int> weak, strong;
  report.weak_components = weak_components(graph, weak);
  report.strong_components = strong_components(graph, strong);

  // Reaches are measured from the lane a place is handled from: half its width plus a slack (the
  // site's road_width where a lane has no width of its own).
  const auto half_lane = [&](int point) {
    const double width = point >= 0 ? graph.points[static_cast<std::size_t>(point)].lane_width : 0.0;
    return 0.5 * (width > 0.0 ? width : map.site.road_width);
  };
  const std::vector<int> area_lines = entry_lines(map.site.file, "loading_areas");
  const std::vector<int> home_lines = entry_lines(map.site.file, "homes");

  const double approach = options.approach_distance > 0.0 ? options.approach_distance : map.site.approach_distance;
  const auto place = [&](const std::string& id, const std::string& key, int line, double x, double y, double slack) {
    PlaceReach p;
    p.id = id;
    p.key = key;
    p.line = line;
    p.approach_x = x;
    p.approach_y = y;
    p.nearest_point = nearest_point(graph, x, y, &p.distance);
    const double reach = half_lane(p.nearest_point) + slack;
    if (p.nearest_point < 0) {
      p.problem = "the road graph is empty";
    } else if (p.distance > reach) {
      p.problem = "position (" + fixed(x) + ", " + fixed(y) + ") is " + fixed(p.distance) +
                  " m from the nearest road graph point; the reach is " + fixed(reach) + " m";
    }
    return p;
  };

  for (std::size_t i = 0; i < map.site.loading_areas.size(); ++i) {
    const LoadingArea& a = map.site.loading_areas[i];
    // The forklift stands on the road side of the pallet, facing it (yaw points to the road).
    const geometry::Pose2 stand = a.approach_pose(approach);
    const double ax = stand.x;
    const double ay = stand.y;
    PlaceReach p = place(a.id, "loading_areas[" + std::to_string(i) + "]", i < area_lines.size() ? area_lines[i] : 0,
                         ax, ay, options.slack);
    if (p.problem.empty()) {
      double pallet_to_road = 0.0;
      const int road_point = nearest_point(graph, a.pose.x, a.pose.y, &pallet_to_road);
      if (pallet_to_road < half_lane(road_point)) {
        p.problem = "the pallet at (" + fixed(a.pose.x) + ", " + fixed(a.pose.y) + ") stands on a road (" +
                    fixed(pallet_to_road) + " m from a lane centre, lane half-width " + fixed(half_lane(road_point)) +
                    " m)";
      }
    }
    report.areas.push_back(std::move(p));
  }
  for (std::size_t i = 0; i < map.site.homes.size(); ++i) {
    const Home& h = map.site.homes[i];
    report.homes.push_back(place(h.id, "homes[" + std::to_string(i) + "]", i < home_lines.size() ? home_lines[i] : 0,
                                 h.pose.x, h.pose.y, options.home_slack));
  }

  // The main component is the strong component most places attach to; a place elsewhere can be
  // reached but not left (or the reverse), so an order through it could never finish.
  std::map<int, int> votes;
  for (const auto* list : {&report.areas, &report.homes}) {
    for (const PlaceReach& p : *list) {
      if (p.problem.empty()) ++votes[strong[static_cast<std::size_t>(p.nearest_point)]];
    }
  }
  int main_component = -1, best = 0;
  for (const auto& [component, count] : votes) {
    if (count > best) {
      best = count;
      main_component = component;
    }
  }
  for (const int c : strong) report.main_component_points += c == main_component ? 1 : 0;
  for (auto* list : {&report.areas, &report.homes}) {
    for (PlaceReach& p : *list) {
      if (p.problem.empty() && strong[static_cast<std::size_t>(p.nearest_point)] != main_component) {
        p.problem = "its nearest road graph point " + std::to_string(p.nearest_point) + " (road " +
                    graph.points[static_cast<std::size_t>(p.nearest_point)].road_id +
                    ") cannot be reached from, or cannot reach, the other places";
      }
      p.reachable = p.problem.empty();
      if (!p.reachable) report.problems.push_back(located(map, p) + p.problem);
    }
  }
  const std::vector<int> rack_lines = entry_lines(map.site.file, "racks");
  for (std::size_t k = 0; k < map.site.racks.size(); ++k) {
    const Rack& rack = map.site.racks[k];
    for (std::size_t i = 0; i < graph.points.size(); ++i) {
      const GraphPoint& a = graph.points[i];
      const auto crosses = [&](int j) {
        const GraphPoint& b = graph.points[static_cast<std::size_t>(j)];
        return geometry::segment_intersects_polygon({a.x, a.y}, {b.x, b.y}, rack.polygon);
      };
      if (std::any_of(graph.successors[i].begin(), graph.successors[i].end(), crosses)) {
        report.problems.push_back(map.site.file + (k < rack_lines.size() ? ":" + std::to_string(rack_lines[k]) : "") +
                                  ": key 'racks[" + std::to_string(k) + "]' (" + rack.id + "): road " + a.road_id +
                                  " runs through the rack");
        break;
      }
    }
  }
  if (map.site.loading_areas.empty())
    report.problems.push_back(map.site.file + ": key 'loading_areas': the site has none");
  return report;
}

SiteMap load_site_map(const std::string& path, const ReachOptions& options) {
  SiteMap map = load_site_map_unchecked(path);
  const SiteReport report = check_site_map(map, options);
  if (!report.usable()) {
    std::string msg = report.problems.front();
    for (std::size_t i = 1; i < report.problems.size(); ++i) msg += "\n" + report.problems[i];
    throw MapError(msg);
  }
  return map;
}

std::string format_report(const SiteReport& r) {
  std::ostringstream out;
  out << "site: " << r.site_file << "\n";
  out << "opendrive: " << r.opendrive_file << "\n";
  out << "roads: " << r.roads << "\n";
  out << "junctions: " << r.junctions << "\n";
  out << "graph points: " << r.points << "\n";
  out << "graph edges: " << r.edges << "\n";
  out << "connected components: " << r.weak_components << " (strongly connected: " << r.strong_components
      << ", main: " << r.main_component_points << " points)\n";
  const auto list = [&](const char* title, const std::vector<PlaceReach>& places) {
    out << title << ": " << places.size() << "\n";
    for (const PlaceReach& p : places) {
      out << "  " << p.id << ": " << (p.reachable ? "reachable" : "NOT reachable") << ", nearest point "
          << p.nearest_point << " at " << fixed(p.distance, 3) << " m";
      if (!p.problem.empty()) out << " (" << p.problem << ")";
      out << "\n";
    }
  };
  list("loading areas", r.areas);
  list("homes", r.homes);
  out << (r.usable() ? "usable: yes" : "usable: no") << "\n";
  return out.str();
}

}  // namespace fleet::map
