// Real OpenDRIVE files written by other tools (see test_data.hpp for where they are) parse, their geometry
// is continuous and their road graph follows their links and junctions.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>
#include <utility>

#include "map/opendrive.hpp"
#include "map/road_graph_builder.hpp"
#include "test_data.hpp"

using namespace fleet::map;

namespace {

std::vector<std::string> shared_files() {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(fleet::test::opendrive_test_data_dir())) {
    if (e.path().extension() == ".xodr") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

bool has_drivable(const Road& r) {
  for (const auto& sec : r.sections) {
    for (const auto* side : {&sec.left, &sec.right}) {
      for (const auto& l : *side) {
        if (l.drivable()) return true;
      }
    }
  }
  return false;
}

/// Unordered pairs of road ids joined by at least one graph edge.
std::set<std::pair<std::string, std::string>> edge_road_pairs(const RoadGraph& g) {
  std::set<std::pair<std::string, std::string>> pairs;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    for (const int j : g.successors[i]) {
      const auto& a = g.points[i].road_id;
      const auto& b = g.points[static_cast<std::size_t>(j)].road_id;
      if (a != b) pairs.insert(std::minmax(a, b));
    }
  }
  return pairs;
}

}  // namespace

TEST(OpenDriveFiles, SharedFilesAreThere) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  EXPECT_GE(shared_files().size(), 5u);
}

TEST(OpenDriveFiles, EveryFileParses) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  for (const std::string& f : shared_files()) {
    SCOPED_TRACE(f);
    RoadNetwork net;
    ASSERT_NO_THROW(net = load_opendrive(f));
    EXPECT_FALSE(net.roads.empty());
    for (const Road& r : net.roads) {
      EXPECT_GT(r.length, 0.0);
      EXPECT_FALSE(r.plan_view.empty());
      EXPECT_FALSE(r.sections.empty());
    }
  }
  const RoadNetwork fab = load_opendrive(fleet::test::opendrive_test_file("fabriksgatan.xodr"));
  EXPECT_EQ(fab.roads.size(), 16u);
  ASSERT_EQ(fab.junctions.size(), 1u);
  EXPECT_EQ(fab.junctions[0].connections.size(), 12u);
}

TEST(OpenDriveFiles, ConsecutiveGeometriesJoinWithinOneMillimetre) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  std::size_t joins = 0;
  for (const std::string& f : shared_files()) {
    const RoadNetwork net = load_opendrive(f);
    for (const Road& r : net.roads) {
      for (std::size_t i = 0; i + 1 < r.plan_view.size(); ++i) {
        const Geometry& g = r.plan_view[i];
        const Geometry& next = r.plan_view[i + 1];
        const RefPoint end = evaluate_geometry(g, g.length);
        EXPECT_NEAR(end.x, next.x, 1e-3) << f << " road " << r.id << " geometry " << i;
        EXPECT_NEAR(end.y, next.y, 1e-3) << f << " road " << r.id << " geometry " << i;
        EXPECT_NEAR(std::remainder(end.hdg - next.hdg, 2.0 * M_PI), 0.0, 1e-3) << f << " road " << r.id;
        ++joins;
      }
    }
  }
  EXPECT_GE(joins, 30u);  // curves, velodrome and e6mini chain many records
}

TEST(OpenDriveFiles, VelodromeClosesItsLoop) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  // One road whose successor is its own start: the end of the reference line meets the start.
  const RoadNetwork net = load_opendrive(fleet::test::opendrive_test_file("velodrome.xodr"));
  const Road& r = net.roads.at(0);
  const RefPoint a = evaluate_reference(r, 0.0);
  const RefPoint b = evaluate_reference(r, r.length);
  EXPECT_NEAR(a.x, b.x, 1e-3);
  EXPECT_NEAR(a.y, b.y, 1e-3);
}

TEST(OpenDriveFiles, GraphConnectivityMatchesLinksAndJunctions) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  for (const std::string& f : shared_files()) {
    SCOPED_TRACE(f);
    const RoadNetwork net = load_opendrive(f);
    const RoadGraph g = build_road_graph(net, {.spacing = 2.0, .single_lane_roads_both_ways = false});
    ASSERT_FALSE(g.points.empty());
    // What the file says is connected, at road level.
    std::set<std::pair<std::string, std::string>> linked;
    for (const Road& r : net.roads) {
      for (const auto* link : {&r.predecessor, &r.successor}) {
        if (!link->has_value() || (*link)->target != LinkTarget::kRoad) continue;
        const Road* o = net.find_road((*link)->element_id);
        if (o != nullptr && o->id != r.id && has_drivable(r) && has_drivable(*o))
          linked.insert(std::minmax(r.id, o->id));
      }
    }
    for (const Junction& j : net.junctions) {
      for (const Connection& c : j.connections) {
        linked.insert(std::minmax(c.incoming_road, c.connecting_road));
      }
    }
    // Every link is an edge and every edge between roads is a link.
    EXPECT_EQ(edge_road_pairs(g), linked);
    // Points have unique ids equal to their index, and every edge stays short (no jumps).
    for (std::size_t i = 0; i < g.points.size(); ++i) {
      EXPECT_EQ(g.points[i].id, static_cast<int>(i));
      for (const int j : g.successors[i]) {
        const auto& a = g.points[i];
        const auto& b = g.points[static_cast<std::size_t>(j)];
        EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 2.5) << a.road_id << "/" << a.lane_id << " -> " << b.road_id;
      }
    }
  }
}

TEST(OpenDriveFiles, LoopRoadWithTwoWayTrafficIsStronglyConnectedPerDirection) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  // velodrome: three right lanes on a closed loop, each a one-way ring along s.
  const RoadNetwork net = load_opendrive(fleet::test::opendrive_test_file("velodrome.xodr"));
  const RoadGraph g = build_road_graph(net, {.spacing = 5.0, .single_lane_roads_both_ways = true});
  std::vector<int> weak, strong;
  EXPECT_EQ(weak_components(g, weak), 3u);
  EXPECT_EQ(strong_components(g, strong), 3u);
  // One way only: along a lane the successor lies ahead in s (or wraps to the start).
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    for (const int j : g.successors[i]) {
      const auto& b = g.points[static_cast<std::size_t>(j)];
      EXPECT_TRUE(b.s > g.points[i].s || b.s == 0.0 || std::abs(b.s - g.points[i].s) < 1e-9);
    }
  }
}

TEST(OpenDriveFiles, JunctionTurnsFollowLaneDirections) {
  FLEET_SKIP_WITHOUT_OPENDRIVE_DATA();
  // fabriksgatan: right lanes drive along s. From incoming road 0's lane 1 (driving against s,
  // so leaving road 0 at its start into junction 4) traffic may enter connecting road 8.
  const RoadNetwork net = load_opendrive(fleet::test::opendrive_test_file("fabriksgatan.xodr"));
  const RoadGraph g = build_road_graph(net, {.spacing = 1.0, .single_lane_roads_both_ways = false});
  bool into = false, out_of = false;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    for (const int j : g.successors[i]) {
      const auto& a = g.points[i];
      const auto& b = g.points[static_cast<std::size_t>(j)];
      if (a.road_id == "0" && a.lane_id == 1 && b.road_id == "8") into = true;
      if (a.road_id == "8" && b.road_id == "0" && b.lane_id == 1) out_of = true;
    }
  }
  EXPECT_TRUE(into);
  EXPECT_FALSE(out_of);  // a one-way connection is not driven backwards
}
