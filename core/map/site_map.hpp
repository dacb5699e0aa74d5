#pragma once

#include <string>
#include <vector>

#include "map/opendrive.hpp"
#include "map/road_graph.hpp"
#include "map/road_graph_builder.hpp"
#include "map/site.hpp"

namespace fleet::map {

/// A site with its road network and road graph, loaded together.
struct SiteMap {
  Site site;
  RoadNetwork network;
  RoadGraphBuild graph;  ///< graph.graph is the RoadGraph planners search
};

/// How a loading area or home is judged reachable. A vehicle handles a load standing on the road
/// centre line facing it, about `approach_distance` from it (0.30 m for the tables' 0.25 x 0.16 m
/// forklifts).
struct ReachOptions {
  double approach_distance = 0.0;  ///< pallet centre to vehicle centre, metres; <= 0: the site's
  /// A graph point must lie within road_width / 2 + slack of the approach position (or of a home).
  double slack = 0.15;
  /// A home may lie within road_width / 2 + home_slack of a graph point: parked forklifts stand
  /// clear of the lanes, where one turning on the spot sweeps, with room beside the lane for a
  /// parked one to turn too (see maps/tools/make_maps.py).
  double home_slack = 0.25;
};

struct PlaceReach {
  std::string id;
  std::string key;  ///< e.g. "loading_areas[3]"
  int line = 0;     ///< line of the entry in the site file, 0 when unknown
  double approach_x = 0.0, approach_y = 0.0;
  int nearest_point = -1;
  double distance = 0.0;   ///< approach position to the nearest graph point, metres
  bool reachable = false;  ///< near the graph and in the site's main strongly connected component
  std::string problem;     ///< empty when usable
};

/// What `fleetctl map check` prints.
struct SiteReport {
  std::string site_file;
  std::string opendrive_file;
  std::size_t roads = 0;
  std::size_t junctions = 0;
  std::size_t points = 0;
  std::size_t edges = 0;
  std::size_t weak_components = 0;
  std::size_t strong_components = 0;
  std::size_t main_component_points = 0;  ///< size of the strong component the places use
  std::vector<PlaceReach> areas;
  std::vector<PlaceReach> homes;
  std::vector<std::string> problems;  ///< each names file, line and key

  bool usable() const { return problems.empty(); }
};

/// Loads the site, its .xodr and builds the graph at the site's graph_spacing, without judging
/// reachability. Throws MapError for unreadable or malformed files.
SiteMap load_site_map_unchecked(const std::string& path, const GraphOptions& graph_options = {});

/// Checks a loaded site: every loading area's approach position and every home near the graph,
/// pallets beside (not on) the roads, every area and home in one strongly connected component
/// so that any pick, drop and return home can be routed.
SiteReport check_site_map(const SiteMap& map, const ReachOptions& options = {});

/// Loads and checks; throws MapError listing every problem when the site is not usable.
SiteMap load_site_map(const std::string& path, const ReachOptions& options = {});

/// The report as text, one fact per line.
std::string format_report(const SiteReport& report);

}  // namespace fleet::map
