// The shipped maps load with their road networks and graphs, every loading area and home is
// reachable, and broken sites are refused with the file and key named.

#include "map/site_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>

#include "geometry/polygon.hpp"
#include "map/reference_samples.hpp"
#include "map/svg_render.hpp"
#include "test_data.hpp"
#include "test_paths.hpp"

using namespace fleet::map;

namespace {

const char* const kShipped[] = {"table_a", "table_b", "warehouse", "plant", "big_warehouse"};

std::string shipped(const std::string& name) {
  return fleet::test::source_path("/maps/") + name + ".yaml";
}

/// Writes a site file next to a copy of table_a.xodr in a fresh temporary folder.
std::string write_site(const std::string& name, const std::string& yaml) {
  const auto dir = std::filesystem::temp_directory_path() / ("fleet_site_map_test_" + name);
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(fleet::test::source_path("/maps/table_a.xodr"), dir / "table_a.xodr",
                             std::filesystem::copy_options::overwrite_existing);
  const auto path = dir / (name + ".yaml");
  std::ofstream(path) << yaml;
  return path.string();
}

const std::string kHead =
    "opendrive: table_a.xodr\n"
    "bounds: {min_x: 0, min_y: 0, max_x: 3, max_y: 3}\n"
    "road_width: 0.30\n"
    "graph_spacing: 0.10\n";

}  // namespace

TEST(SiteMap, ShippedMapsLoadAndEveryPlaceIsReachable) {
  for (const char* name : kShipped) {
    SCOPED_TRACE(name);
    SiteMap map;
    ASSERT_NO_THROW(map = load_site_map(shipped(name)));
    const SiteReport report = check_site_map(map);
    EXPECT_TRUE(report.usable()) << format_report(report);
    EXPECT_EQ(report.weak_components, 1u);
    EXPECT_EQ(report.strong_components, 1u);  // every road is driven both ways and connected
    for (const auto& a : report.areas) EXPECT_TRUE(a.reachable) << a.id << ": " << a.problem;
    for (const auto& h : report.homes) EXPECT_TRUE(h.reachable) << h.id << ": " << h.problem;
  }
}

TEST(SiteMap, DemoTablesHaveWhatTheDemoNeeds) {
  for (const char* name : {"table_a", "table_b"}) {
    SCOPED_TRACE(name);
    const SiteMap map = load_site_map(shipped(name));
    const Site& s = map.site;
    EXPECT_NEAR(s.bounds.max_x - s.bounds.min_x, 3.0, 1e-9);
    EXPECT_NEAR(s.bounds.max_y - s.bounds.min_y, 3.0, 1e-9);
    EXPECT_NEAR(s.road_width, 0.30, 1e-9);
    EXPECT_GE(s.loading_areas.size(), 6u);
    EXPECT_GE(s.static_obstacles.size(), 3u);
    EXPECT_EQ(s.uwb_anchors.size(), 4u);
    ASSERT_GE(s.homes.size(), 4u);
    EXPECT_EQ(s.homes[0].id, "H1");
    EXPECT_FALSE(map.network.junctions.empty());
    for (const auto& u : s.uwb_anchors) EXPECT_NEAR(u.z, 1.0, 0.3);
    // Roads 30 cm wide: every lane of every road.
    for (const Road& r : map.network.roads) {
      EXPECT_NEAR(lane_width_at(r, 0, -1, 0.0), 0.30, 1e-9) << r.id;
    }
  }
}

TEST(SiteMap, EveryDesignatedObstacleCutsARoad) {
  for (const char* name : kShipped) {
    const SiteMap map = load_site_map(shipped(name));
    const RoadGraph& g = map.graph.graph;
    for (const StaticObstacle& o : map.site.static_obstacles) {
      EXPECT_FALSE(o.enabled_at_start) << name << " " << o.id;
      bool cuts = false;
      for (std::size_t i = 0; i < g.points.size() && !cuts; ++i) {
        for (const int j : g.successors[i]) {
          const auto& a = g.points[i];
          const auto& b = g.points[static_cast<std::size_t>(j)];
          if (fleet::geometry::segment_intersects_polygon({a.x, a.y}, {b.x, b.y}, o.polygon)) cuts = true;
        }
      }
      EXPECT_TRUE(cuts) << name << " " << o.id;
    }
  }
}

TEST(SiteMap, ParkedForkliftsAndPalletsStayOffTheRoads) {
  // A forklift at home and a pallet must not stand on any lane: every footprint corner and the
  // centre lie at least half a road width from every lane centre segment. The plant parks its
  // vehicles at the ends of stalls of their own (PlantMap tests).
  for (const char* name : {"table_a", "table_b", "warehouse"}) {
    const SiteMap map = load_site_map(shipped(name));
    const double half = 0.5 * map.site.road_width;
    for (const Home& h : map.site.homes) {
      for (const auto& c : fleet::geometry::footprint_polygon(h.pose, {0.25, 0.16})) {
        EXPECT_GE(distance_to_graph(map.graph.graph, c.x, c.y), half - 1e-9) << name << " " << h.id;
      }
    }
    for (const LoadingArea& a : map.site.loading_areas) {
      for (const auto& c : fleet::geometry::footprint_polygon(a.pose, {0.12, 0.12})) {
        EXPECT_GE(distance_to_graph(map.graph.graph, c.x, c.y), half) << name << " " << a.id;
      }
      EXPECT_TRUE(map.site.bounds.contains(a.pose.position()));
    }
  }
}

TEST(SiteMap, GraphPointsHaveUniqueIdsAndLieOnTheRoads) {
  const SiteMap map = load_site_map(shipped("table_a"));
  const RoadGraph& g = map.graph.graph;
  ASSERT_EQ(g.points.size(), g.successors.size());
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    EXPECT_EQ(g.points[i].id, static_cast<int>(i));
    EXPECT_EQ(g.points[i].lane_id, -1);
    const Road* r = map.network.find_road(g.points[i].road_id);
    ASSERT_NE(r, nullptr);
    const RefPoint ref = evaluate_reference(*r, g.points[i].s);
    EXPECT_NEAR(ref.x, g.points[i].x, 1e-9);  // lane centre on the reference line
    EXPECT_NEAR(ref.y, g.points[i].y, 1e-9);
    for (const int j : g.successors[i]) {
      const auto& b = g.points[static_cast<std::size_t>(j)];
      EXPECT_LE(std::hypot(b.x - g.points[i].x, b.y - g.points[i].y), map.site.graph_spacing + 1e-9);
      // Both ways: single-lane roads.
      const auto& back = g.successors[static_cast<std::size_t>(j)];
      EXPECT_NE(std::find(back.begin(), back.end(), static_cast<int>(i)), back.end());
    }
  }
}

TEST(SiteMap, UnreachableLoadingAreaIsNamedWithFileLineAndKey) {
  const std::string path = write_site("unreachable", kHead +
                                                         "loading_areas:\n"
                                                         "  - {id: A1, x: 0.975, y: 0.15, yaw: 1.5707963}\n"
                                                         "  - {id: A2, x: 0.15, y: 0.975, yaw: 3.1415927}\n");
  try {
    load_site_map(path);
    FAIL() << "A2 faces the table edge, away from every road";
  } catch (const MapError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path + ":7: key 'loading_areas[1]' (A2)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("from the nearest road graph point"), std::string::npos) << msg;
    EXPECT_EQ(msg.find("(A1)"), std::string::npos) << msg;
  }
}

TEST(SiteMap, PalletOnTheRoadIsRefused) {
  // Facing the road but standing on it: the approach point is near a road, the pallet is too.
  const std::string path =
      write_site("on_road", kHead + "loading_areas:\n  - {id: A1, x: 0.975, y: 0.40, yaw: 1.5707963}\n");
  const SiteReport report = check_site_map(load_site_map_unchecked(path));
  ASSERT_FALSE(report.usable());
  EXPECT_NE(report.problems[0].find("stands on a road"), std::string::npos) << report.problems[0];
}

TEST(SiteMap, AreaFacingAwayFromTheRoadIsUnreachable) {
  const std::string path =
      write_site("away", kHead + "loading_areas:\n  - {id: A1, x: 0.975, y: 0.15, yaw: -1.5707963}\n");
  const SiteReport report = check_site_map(load_site_map_unchecked(path));
  ASSERT_EQ(report.areas.size(), 1u);
  EXPECT_FALSE(report.areas[0].reachable);
}

TEST(SiteMap, BadSiteFilesAreNamed) {
  const auto message = [](const std::string& name, const std::string& yaml) {
    try {
      load_site_map(write_site(name, yaml));
    } catch (const MapError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message("unknown", kHead + "colour: red\n").find("unknown key 'colour'"), std::string::npos);
  EXPECT_NE(message("dup", kHead + "loading_areas:\n  - {id: A1, x: 0.975, y: 0.15, yaw: 1.57}\n"
                                   "  - {id: A1, x: 2.025, y: 0.15, yaw: 1.57}\n")
                .find("duplicate id 'A1'"),
            std::string::npos);
  EXPECT_NE(message("outside", kHead + "static_obstacles:\n  - {id: O1, polygon: [[1, 1], [4, 1], [4, 2]]}\n")
                .find("obstacle 'O1' lies outside the bounds"),
            std::string::npos);
  EXPECT_NE(message("noxodr", "bounds: {min_x: 0, min_y: 0, max_x: 3, max_y: 3}\n").find("key 'opendrive' is missing"),
            std::string::npos);
  const std::string missing =
      message("missing", "opendrive: nowhere.xodr\nbounds: {min_x: 0, min_y: 0, max_x: 3, max_y: 3}\n");
  EXPECT_NE(missing.find("nowhere.xodr: cannot open"), std::string::npos) << missing;
}

TEST(SiteMap, ReportListsTheFacts) {
  const SiteMap map = load_site_map(shipped("table_a"));
  const std::string text = format_report(check_site_map(map));
  EXPECT_NE(text.find("roads: " + std::to_string(map.network.roads.size())), std::string::npos) << text;
  EXPECT_NE(text.find("graph points: " + std::to_string(map.graph.graph.points.size())), std::string::npos);
  EXPECT_NE(text.find("connected components: 1"), std::string::npos);
  EXPECT_NE(text.find("A8: reachable"), std::string::npos);
  EXPECT_NE(text.find("usable: yes"), std::string::npos);
}

TEST(ReferenceSamples, CoverEveryRoadFromZeroToItsLengthInclusive) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  const RoadNetwork net = load_opendrive(fleet::test::opendrive_test_file("curves.xodr"));
  const auto samples = sample_reference_lines(net, 0.5);
  ASSERT_FALSE(samples.empty());
  EXPECT_DOUBLE_EQ(samples.front().s, 0.0);
  EXPECT_DOUBLE_EQ(samples.back().s, net.roads.back().length);
  EXPECT_EQ(samples.size(), static_cast<std::size_t>(std::floor(net.roads[0].length / 0.5)) + 2);
  for (std::size_t i = 1; i < samples.size(); ++i) {
    // Consecutive samples are at most one step apart (a chord is no longer than its arc); the
    // slack covers the file's own rounding where one geometry record hands over to the next.
    EXPECT_LE(std::hypot(samples[i].x - samples[i - 1].x, samples[i].y - samples[i - 1].y), 0.5 + 1e-4);
  }
  EXPECT_THROW(sample_reference_lines(net, 0.0), MapError);
  EXPECT_THROW(sample_reference_lines(net, std::nan("")), MapError);
}

TEST(SvgRender, DrawsEveryLayerOfTheSite) {
  const SiteMap map = load_site_map(shipped("table_b"));
  const std::string svg = render_svg(map);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  for (const char* layer :
       {"lanes", "reference", "graph-edges", "graph-points", "obstacles", "loading-areas", "homes", "uwb-anchors"}) {
    EXPECT_NE(svg.find(std::string("id=\"") + layer + "\""), std::string::npos) << layer;
  }
  for (const auto& a : map.site.loading_areas) EXPECT_NE(svg.find(">" + a.id + "</text>"), std::string::npos) << a.id;
  for (const auto& h : map.site.homes) EXPECT_NE(svg.find(">" + h.id + "</text>"), std::string::npos) << h.id;
  // One <line> per graph edge.
  std::size_t lines = 0;
  for (std::size_t at = svg.find("<line x1"); at != std::string::npos; at = svg.find("<line x1", at + 1)) ++lines;
  EXPECT_EQ(lines, map.graph.graph.edge_count() + map.site.loading_areas.size() + map.site.homes.size());
}

TEST(SiteMap, AnySingleObstacleLeavesEveryAreaReachable) {
  // A designated obstacle closes a road, not a loading area: with any one of them switched on
  // (points within a forklift half-length of it removed) every area and home is still served
  // by one strongly connected part of the graph, thanks to the loops.
  for (const char* name : kShipped) {
    const SiteMap map = load_site_map(shipped(name));
    const RoadGraph& full = map.graph.graph;
    const SiteReport report = check_site_map(map);
    for (const StaticObstacle& o : map.site.static_obstacles) {
      const auto box = fleet::geometry::bounding_box(o.polygon);
      const double grow = 0.13;
      const auto blocked = [&](const GraphPoint& p) {
        return p.x >= box.min_x - grow && p.x <= box.max_x + grow && p.y >= box.min_y - grow && p.y <= box.max_y + grow;
      };
      RoadGraph cut = full;
      for (std::size_t i = 0; i < cut.points.size(); ++i) {
        auto& succ = cut.successors[i];
        if (blocked(cut.points[i])) {
          succ.clear();
          continue;
        }
        std::erase_if(succ, [&](int j) { return blocked(cut.points[static_cast<std::size_t>(j)]); });
      }
      std::vector<int> strong;
      strong_components(cut, strong);
      std::map<int, int> count;
      for (const auto* places : {&report.areas, &report.homes}) {
        for (const PlaceReach& p : *places) {
          EXPECT_FALSE(blocked(full.points[static_cast<std::size_t>(p.nearest_point)]))
              << name << ": " << o.id << " covers the approach of " << p.id;
          ++count[strong[static_cast<std::size_t>(p.nearest_point)]];
        }
      }
      EXPECT_EQ(count.size(), 1u) << name << ": with " << o.id << " on, the places fall apart";
    }
  }
}
