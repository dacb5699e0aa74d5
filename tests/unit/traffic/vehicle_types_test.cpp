// Traffic with several vehicle types: places per type, conflicts per pair of types, lanes per
// type, and the two lanes of one road.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "map/site_map.hpp"
#include "test_graphs.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_settings.hpp"
#include "traffic/traffic_sim.hpp"
#include "traffic/vehicle_lanes.hpp"

namespace fleet::traffic {
namespace {

using testing::point_at;

constexpr int kSmall = 0;
constexpr int kBig = 1;

// A small type (0.3 x 0.2 m) and a big one.
TrafficConfiguration two_types(double big_length, double big_width) {
  TrafficConfiguration c;
  c.resources.margin = 0.05;
  c.resources.vehicle_types = {{"small", rectangle_footprint({0.3, 0.2})},
                               {"big", rectangle_footprint({big_length, big_width})}};
  return c;
}

SimParams scripted(std::vector<int> types) {
  SimParams p;
  p.random_trips = false;
  p.dwell = 0.5;
  p.robot_types = std::move(types);
  return p;
}

// Appends a lane driven one way from (x0, y0) to (x1, y1), sampled every 0.1 m, continuing from
// point `from` when it is given; returns the point ids.
std::vector<int> lane(map::RoadGraph& g, int from, double x0, double y0, double x1, double y1, const std::string& road,
                      int lane_id) {
  const int steps = static_cast<int>(std::lround(std::hypot(x1 - x0, y1 - y0) / 0.1));
  std::vector<int> ids;
  if (from >= 0) ids.push_back(from);
  for (int k = from >= 0 ? 1 : 0; k <= steps; ++k) {
    const double t = static_cast<double>(k) / steps;
    map::GraphPoint p;
    p.id = static_cast<int>(g.points.size());
    p.x = x0 + t * (x1 - x0);
    p.y = y0 + t * (y1 - y0);
    p.road_id = road;
    p.lane_id = lane_id;
    g.points.push_back(p);
    g.successors.emplace_back();
    if (!ids.empty()) g.successors[static_cast<std::size_t>(ids.back())].push_back(p.id);
    ids.push_back(p.id);
  }
  return ids;
}

// A two-lane road "r" from x = 0 to x = 6, keep right: lane -1 eastwards at y = -0.3, lane 1
// westwards at y = 0.3. Lanes of their own lead onto it and away from it at 45 degrees.
struct TwoLaneRoad {
  map::RoadGraph graph;
  int east_start = 0, east_goal = 0, west_start = 0, west_goal = 0;
};

TwoLaneRoad two_lane_road() {
  TwoLaneRoad r;
  auto& g = r.graph;
  const auto in_east = lane(g, -1, -2.0, -2.3, 0.0, -0.3, "a", -1);
  const auto east = lane(g, in_east.back(), 0.0, -0.3, 6.0, -0.3, "r", -1);
  const auto out_east = lane(g, east.back(), 6.0, -0.3, 8.0, -2.3, "c", -1);
  const auto in_west = lane(g, -1, 8.0, 2.3, 6.0, 0.3, "b", -1);
  const auto west = lane(g, in_west.back(), 6.0, 0.3, 0.0, 0.3, "r", 1);
  const auto out_west = lane(g, west.back(), 0.0, 0.3, -2.0, 2.3, "d", -1);
  for (int id : {east.front(), west.front()}) g.points[static_cast<std::size_t>(id)].road_id = "r";
  r.east_start = in_east.front();
  r.east_goal = out_east.back();
  r.west_start = in_west.front();
  r.west_goal = out_west.back();
  return r;
}

bool on_the_road(const geometry::Pose2& pose) {
  return pose.x > 0.05 && pose.x < 5.95;
}

// Drives both robots to their goals; returns whether they were ever on the shared road together.
bool drive_head_on(TrafficSim& sim, bool& both_arrived) {
  bool together = false;
  while (sim.time() < 400.0 && !(sim.idle(1) && sim.idle(2))) {
    sim.step();
    EXPECT_EQ(sim.report().invariant_violations, 0u) << sim.report().first_violation;
    EXPECT_EQ(sim.report().collisions, 0u) << sim.report().first_collision;
    together = together || (on_the_road(sim.pose(1)) && on_the_road(sim.pose(2)));
  }
  both_arrived = sim.goals_reached(1) == 1u && sim.goals_reached(2) == 1u;
  return together;
}

TEST(VehicleTypes, SmallRobotsPassEachOtherOnATwoLaneRoadBigOnesTakeItInTurn) {
  const auto road = two_lane_road();
  for (int type : {kSmall, kBig}) {
    SCOPED_TRACE(type == kSmall ? "small" : "big");
    TrafficSim sim(road.graph, two_types(1.0, 1.0), scripted({type, type}), {}, {road.east_start, road.west_start});
    sim.add_goal(1, road.east_goal);
    sim.add_goal(2, road.west_goal);
    bool both_arrived = false;
    const bool together = drive_head_on(sim, both_arrived);
    EXPECT_TRUE(both_arrived);
    EXPECT_EQ(together, type == kSmall);
    EXPECT_EQ(sim.report().deadlocks, 0u);
  }
}

TEST(VehicleTypes, ABigRobotWaitsForASmallOneOnlyWhereTheirRegionsMeet) {
  // Regions per pair of types: small beside small clear the centre line, big beside small do not.
  const auto road = two_lane_road();
  const ConflictZones zones(road.graph, two_types(1.0, 1.0).resources);
  const int east = zones.place_of(point_at(road.graph, 3.0, -0.3));
  const int west = zones.place_of(point_at(road.graph, 3.0, 0.3));
  EXPECT_FALSE(zones.conflict(kSmall, east, kSmall, west));
  EXPECT_TRUE(zones.conflict(kBig, east, kSmall, west));
  EXPECT_TRUE(zones.conflict(kSmall, east, kBig, west));
  EXPECT_TRUE(zones.conflict(kBig, east, kBig, west));
  EXPECT_TRUE(zones.opposite_lanes(kSmall, zones.corridor(east), kSmall).empty());
  EXPECT_FALSE(zones.opposite_lanes(kBig, zones.corridor(east), kSmall).empty());
}

TEST(VehicleTypes, AWaitCycleAcrossTwoTypesIsBroken) {
  {
    // Head-on in a single-lane corridor: a small and a big robot, one backs off into the siding.
    const auto g = testing::corridor_with_siding();
    TrafficSim sim(g, two_types(0.32, 0.26), scripted({kSmall, kBig}), {},
                   {point_at(g, 0.0, 0.0), point_at(g, 2.0, 0.0)});
    sim.add_goal(1, point_at(g, 2.0, 0.0));
    sim.add_goal(2, point_at(g, 0.0, 0.0));
    bool both_arrived = false;
    drive_head_on(sim, both_arrived);
    EXPECT_TRUE(both_arrived);
    EXPECT_GE(sim.report().sidings, 1u);
    EXPECT_EQ(sim.report().deadlocks, 0u);
  }
  {
    // Three robots at a crossing, each wanting the arm end where the next stands.
    const auto g = testing::plus_junction(1.5);
    const int e = point_at(g, 1.5, 0.0), n = point_at(g, 0.0, 1.5), w = point_at(g, -1.5, 0.0);
    TrafficSim sim(g, two_types(0.32, 0.26), scripted({kSmall, kBig, kSmall}), {}, {e, n, w});
    sim.add_goal(1, n);
    sim.add_goal(2, w);
    sim.add_goal(3, e);
    bool big_in_a_cycle = false;  // a siding or re-route instruction breaking a cycle with robot 2 in it
    while (sim.time() < 600.0 && !(sim.idle(1) && sim.idle(2) && sim.idle(3))) {
      sim.step();
      ASSERT_EQ(sim.report().invariant_violations, 0u) << sim.report().first_violation;
      ASSERT_EQ(sim.report().collisions, 0u) << sim.report().first_collision;
      for (const auto& event : sim.last_update().events) {
        const bool breaks =
            event.kind == TrafficEvent::Kind::kDeadlockResolved || event.kind == TrafficEvent::Kind::kSidingSent;
        const bool with_big = event.robot_id == 2 || std::count(event.others.begin(), event.others.end(), 2) > 0;
        big_in_a_cycle = big_in_a_cycle || (breaks && with_big);
      }
    }
    for (int id : {1, 2, 3}) EXPECT_EQ(sim.goals_reached(id), 1u) << "robot " << id;
    EXPECT_TRUE(big_in_a_cycle);
    EXPECT_EQ(sim.report().deadlocks, 0u);
  }
}

// Two ways between junctions L (0, 0) and R (1.5, 0): the straight one a narrow lane (0.3 m), the
// one round by y = 0.9 wide (1 m).
map::RoadGraph narrow_shortcut() {
  auto g = testing::two_ways_between_junctions();
  for (auto& p : g.points) {
    const bool straight = std::abs(p.y) < 1e-9 && p.x > 1e-9 && p.x < 1.5 - 1e-9;
    p.lane_width = straight ? 0.3 : 1.0;
  }
  return g;
}

bool enters_narrow(const map::RoadGraph& g, const std::vector<int>& route) {
  return std::any_of(route.begin() + 1, route.end(),
                     [&](int id) { return g.points[static_cast<std::size_t>(id)].lane_width < 0.5; });
}

TEST(VehicleTypes, ARobotIsNeverRoutedIntoALaneItsTypeDoesNotFit) {
  const auto g = narrow_shortcut();
  TrafficConfiguration config = two_types(0.5, 0.4);
  config.one_way = false;
  config.reroute_wait = 2.0;
  // Planning graphs: no edge into the narrow lane for the big type, the small one keeps it.
  const auto edges_into_narrow = [&](const map::RoadGraph& graph) {
    int n = 0;
    for (const auto& next : graph.successors) {
      for (int j : next) n += g.points[static_cast<std::size_t>(j)].lane_width < 0.5 ? 1 : 0;
    }
    return n;
  };
  EXPECT_EQ(edges_into_narrow(planning_graph(g, config, kBig)), 0);
  EXPECT_GT(edges_into_narrow(planning_graph(g, config, kSmall)), 0);
  EXPECT_EQ(edges_into_narrow(lane_graph_for(g, 0.4, 0.05)), 0);
  EXPECT_EQ(edges_into_narrow(lane_graph_for(g, 0.2, 0.05)), edges_into_narrow(g));

  const int west = point_at(g, -0.6, 0.0), east = point_at(g, 2.1, 0.0);
  const int top = point_at(g, 0.7, 0.9);
  for (int type : {kBig, kSmall}) {
    SCOPED_TRACE(type == kBig ? "big" : "small");
    TrafficManager manager(g, config);
    ASSERT_TRUE(manager.set_robot_type(1, type));
    RouteSearch full(g, manager.zones());
    const std::vector<int> straight = full.shortest(west, east);
    ASSERT_TRUE(enters_narrow(g, straight));
    EXPECT_EQ(manager.submit_route({1, 1, straight}, 0.0) == SubmitStatus::kInvalid, type == kBig);
    // Round by the top, where a robot stands at its goal: the robot waits, then is re-routed
    // round it if its type fits another way.
    TrafficManager blocked(g, config);
    ASSERT_TRUE(blocked.set_robot_type(1, type));
    const std::vector<int> round = blocked.search(type).shortest(west, east, nullptr);
    std::vector<std::uint8_t> no_straight(blocked.zones().place_count(), 0);
    for (int id : straight) {
      if (g.points[static_cast<std::size_t>(id)].lane_width < 0.5)
        no_straight[static_cast<std::size_t>(blocked.zones().place_of(id))] = 1;
    }
    const std::vector<int> detour = full.shortest(west, east, &no_straight);
    ASSERT_FALSE(enters_narrow(g, detour));
    ASSERT_EQ(blocked.submit_route({1, 1, detour}, 0.0), SubmitStatus::kAccepted);
    ASSERT_EQ(blocked.submit_route({2, 1, {top}}, 0.0), SubmitStatus::kAccepted);
    EXPECT_EQ(enters_narrow(g, round), type == kSmall);
    bool rerouted_through_narrow = false;
    for (double t = 0.0; t < 20.0; t += 0.1) {
      blocked.update(t);
      ASSERT_EQ(blocked.check_invariant(), "");
      rerouted_through_narrow = rerouted_through_narrow || enters_narrow(g, blocked.route(1));
    }
    EXPECT_EQ(rerouted_through_narrow, type == kSmall);
  }
}

TEST(VehicleTypes, GraphPointsCarryTheirLaneWidthFromOpenDrive) {
  // table_a's lanes are 0.3 m wide (<width a="0.3">): a 0.16 m robot with 0.03 m margin fits them
  // all, a 0.3 m one none.
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto& g = site.graph.graph;
  for (const auto& p : g.points) ASSERT_DOUBLE_EQ(p.lane_width, 0.3) << "point " << p.id;
  EXPECT_EQ(lane_graph_for(g, 0.16, 0.03).successors, g.successors);
  EXPECT_EQ(lane_graph_for(g, 0.3, 0.03).edge_count(), 0u);
}

TEST(VehicleTypes, OneTypeGivesTheConflictsOfTheFootprintRectangle) {
  // The regions as the single-footprint zones define them, computed here from the rectangle
  // directly: for every edge at a place, the hull of the footprint at the place and at the
  // edge's midpoint, grown by margin / 2.
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto& g = site.graph.graph;
  ResourceParams rectangle;
  rectangle.footprint = {0.25, 0.16};
  rectangle.margin = 0.03;
  ResourceParams typed = rectangle;
  typed.vehicle_types = {{"forklift", rectangle_footprint(rectangle.footprint)},
                         {"twin", rectangle_footprint(rectangle.footprint)}};
  const ConflictZones one(g, rectangle);
  const ConflictZones two(g, typed);
  ASSERT_EQ(one.place_count(), two.place_count());
  std::vector<std::vector<geometry::Polygon>> region(one.place_count());
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    for (int j : g.successors[i]) {
      for (auto [a, b] : {std::pair{i, static_cast<std::size_t>(j)}, std::pair{static_cast<std::size_t>(j), i}}) {
        if (one.place_of(static_cast<int>(a)) == one.place_of(static_cast<int>(b))) continue;
        const auto& pa = g.points[a];
        const auto& pb = g.points[b];
        const double heading = std::atan2(pb.y - pa.y, pb.x - pa.x);
        auto corners = geometry::footprint_polygon({pa.x, pa.y, heading}, rectangle.footprint, rectangle.margin / 2);
        const auto far = geometry::footprint_polygon({(pa.x + pb.x) / 2, (pa.y + pb.y) / 2, heading},
                                                     rectangle.footprint, rectangle.margin / 2);
        corners.insert(corners.end(), far.begin(), far.end());
        region[static_cast<std::size_t>(one.place_of(static_cast<int>(a)))].push_back(convex_hull(corners));
      }
    }
  }
  std::size_t pairs = 0;
  for (std::size_t p = 0; p < region.size(); ++p) {
    std::vector<int> expected;
    for (std::size_t q = 0; q < region.size(); ++q) {
      bool overlap = p == q;
      for (const auto& a : region[p]) {
        for (const auto& b : region[q]) overlap = overlap || geometry::convex_polygons_overlap(a, b);
      }
      if (overlap) expected.push_back(static_cast<int>(q));
    }
    pairs += expected.size();
    EXPECT_EQ(one.conflicts(static_cast<int>(p)), expected) << "place " << p;
    for (int a : {0, 1}) {
      for (int b : {0, 1}) EXPECT_EQ(two.conflicts(a, static_cast<int>(p), b), expected) << "place " << p;
    }
    EXPECT_EQ(one.stoppable(static_cast<int>(p)), two.stoppable(1, static_cast<int>(p)));
  }
  EXPECT_GT(pairs, 2 * region.size());  // places do conflict with their neighbours
  EXPECT_EQ(one_way_plan(g, one).graph.successors, one_way_plan(g, two).graph.successors);
}

}  // namespace
}  // namespace fleet::traffic
