#include "coordination/place_pibt.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <string>

#include "../traffic/test_graphs.hpp"
#include "config/fleet_config.hpp"
#include "coordination/place_sim.hpp"
#include "forklift_places.hpp"
#include "map/site_map.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_settings.hpp"
#include "traffic/traffic_sim.hpp"

namespace fleet::coordination {
namespace {

using testing::forklift_params;

TEST(PlaceGraph, DistancesFollowTheLanesOneWay) {
  traffic::testing::GraphBuilder b;
  const std::vector<int> lane = b.one_way_road(0.0, 0.0, 1.0, 0.0);
  const traffic::ConflictZones zones(b.graph(), forklift_params());
  PlaceGraph graph(b.graph(), zones);
  const int first = zones.place_of(lane.front());
  const int last = zones.place_of(lane.back());
  EXPECT_NEAR(graph.distance(0, first, last), 1.0, 1e-9);
  EXPECT_EQ(graph.distance(0, last, first), PlaceGraph::kUnreachable);
  EXPECT_EQ(graph.successors(0, last).size(), 0u);
  EXPECT_EQ(graph.predecessors(0, last).size(), 1u);
}

// Plain Dijkstra backwards from `goal` over the type's moves: the metres from every place.
std::vector<double> dijkstra_to(const PlaceGraph& graph, int type, int goal) {
  std::vector<double> metres(static_cast<std::size_t>(graph.place_count()), PlaceGraph::kUnreachable);
  std::vector<bool> done(metres.size(), false);
  metres[static_cast<std::size_t>(goal)] = 0.0;
  for (;;) {
    int next = -1;
    for (int place = 0; place < graph.place_count(); ++place) {
      const auto p = static_cast<std::size_t>(place);
      if (!done[p] && metres[p] < PlaceGraph::kUnreachable &&
          (next < 0 || metres[p] < metres[static_cast<std::size_t>(next)])) {
        next = place;
      }
    }
    if (next < 0) return metres;
    done[static_cast<std::size_t>(next)] = true;
    for (const int before : graph.predecessors(type, next)) {
      const double via = metres[static_cast<std::size_t>(next)] + graph.step_length(before, next);
      metres[static_cast<std::size_t>(before)] = std::min(metres[static_cast<std::size_t>(before)], via);
    }
  }
}

// The search towards the first place asked for goes on for places asked later: every answer, in
// any order, for every vehicle type of the plant (one-way lanes, types that fit fewer lanes and
// places they cannot reach), is the shortest way's length.
TEST(PlaceGraph, DistancesAskedInAnyOrderAreTheShortestWays) {
  const auto config = config::load_fleet_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/plant.yaml");
  const traffic::ConflictZones zones(site.graph.graph, traffic::configuration_from(config).resources);
  PlaceGraph graph(site.graph.graph, zones);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> any_place(0, graph.place_count() - 1);
  std::size_t unreachable = 0;
  for (int type = 0; type < graph.type_count(); ++type) {
    for (int goal_index = 0; goal_index < 3; ++goal_index) {
      const int goal = any_place(rng);
      const std::vector<double> expected = dijkstra_to(graph, type, goal);
      for (int ask = 0; ask < 200; ++ask) {
        const int place = any_place(rng);
        const double metres = graph.distance(type, place, goal);
        const double shortest = expected[static_cast<std::size_t>(place)];
        if (shortest == PlaceGraph::kUnreachable) {
          EXPECT_EQ(metres, PlaceGraph::kUnreachable) << "type " << type << " place " << place << " goal " << goal;
          ++unreachable;
        } else {
          EXPECT_NEAR(metres, shortest, 1e-9) << "type " << type << " place " << place << " goal " << goal;
        }
      }
    }
  }
  EXPECT_GT(graph.places_settled(), 0u);
  EXPECT_LT(unreachable, 4u * 3u * 200u);
}

// A robot on a one-way lane stands behind one held at its place: a body that backs up tries
// backing up along the lane after standing a while, a tricycle (which would pivot round first,
// sweeping the ground about it) is only ever moved forwards, so it waits.
TEST(PlacePibt, ATypeThatDoesNotBackUpIsNeverMovedBackAlongItsLane) {
  traffic::testing::GraphBuilder b;
  b.one_way_road(0.0, 0.0, 2.0, 0.0);
  traffic::ResourceParams params = forklift_params();
  const geometry::Polygon body = traffic::rectangle_footprint(params.footprint);
  params.vehicle_types = {{"forklift", body, 0.0, {}, true}, {"tricycle", body, 0.0, {}, false}};
  const traffic::ConflictZones zones(b.graph(), params);
  const auto place_at = [&](double x) { return zones.place_of(traffic::testing::point_at(b.graph(), x, 0.0)); };
  for (const int type : {0, 1}) {
    PlaceGraph graph(b.graph(), zones);
    PlacePibt planner(graph, 1);
    std::vector<PlaceRobot> robots{{type, place_at(1.0), place_at(2.0), false}, {0, place_at(1.4), -1, true}};
    double least_x = 1.0;
    for (int step = 0; step < 20; ++step) {
      const std::vector<int> next = planner.plan(robots);
      ASSERT_EQ(broken_step_rule(zones, robots, next), "") << "step " << step;
      for (std::size_t i = 0; i < robots.size(); ++i) robots[i].place = next[i];
      least_x = std::min(least_x, zones.position(robots[0].place).x);
    }
    if (type == 0) {
      EXPECT_LT(least_x, 1.0 - 1e-6) << "a forklift backs up along the lane";
    } else {
      EXPECT_NEAR(least_x, 1.0, 1e-6) << "a tricycle is never moved against its lane";
    }
  }
}

// A tricycle (it does not back up) waits at a branch to turn into a single-lane corridor down
// which a forklift comes towards it: it keeps out until the forklift is through the junction,
// rather than drive in nose to nose with it (the forklift would have to back off the whole way).
TEST(PlacePibt, ARobotThatCannotBackUpWaitsOutsideAStretchOneComesDownTowardsIt) {
  traffic::testing::GraphBuilder b;
  b.road(-1.0, 0.0, 0.0, 0.0);
  b.road(0.0, 0.0, 2.0, 0.0);
  b.road(0.0, -1.0, 0.0, 0.0);
  traffic::ResourceParams params = forklift_params();
  const geometry::Polygon body = traffic::rectangle_footprint(params.footprint);
  params.vehicle_types = {{"forklift", body, 0.0, {}, true}, {"tricycle", body, 0.0, {}, false}};
  const traffic::ConflictZones zones(b.graph(), params);
  const auto at = [&](double x, double y) { return zones.place_of(traffic::testing::point_at(b.graph(), x, y)); };
  PlaceGraph graph(b.graph(), zones);
  PlacePibt planner(graph, 3);
  const std::vector<int> goals{at(1.8, 0.0), at(-0.8, 0.0)};
  std::vector<PlaceRobot> robots{{1, at(0.0, -0.8), goals[0], false}, {0, at(1.4, 0.0), goals[1], false}};
  bool nose_to_nose = false;
  int step = 0;
  for (; step < 200 && (robots[0].place != goals[0] || robots[1].place != goals[1]); ++step) {
    const std::vector<int> next = planner.plan(robots);
    ASSERT_EQ(broken_step_rule(zones, robots, next), "") << "step " << step;
    for (std::size_t i = 0; i < robots.size(); ++i) robots[i].place = next[i];
    const geometry::Vec2 tricycle = zones.position(robots[0].place);
    const geometry::Vec2 forklift = zones.position(robots[1].place);
    // Both on the corridor, the forklift east of the tricycle: it has not come through yet.
    nose_to_nose = nose_to_nose || (tricycle.x > 0.05 && forklift.x > tricycle.x);
  }
  EXPECT_FALSE(nose_to_nose) << "the tricycle drove into the corridor towards the forklift";
  EXPECT_EQ(robots[0].place, goals[0]);
  EXPECT_EQ(robots[1].place, goals[1]);
}

// Two robots meet head-on in a single-lane corridor with a siding: the one pushed backs into the
// siding and both get through.
TEST(PlacePibt, HeadOnInACorridorOneStepsIntoTheSiding) {
  const map::RoadGraph road = traffic::testing::corridor_with_siding();
  const traffic::ConflictZones zones(road, forklift_params());
  PlaceGraph graph(road, zones);
  PlacePibt planner(graph, 1);
  const int west = zones.place_of(traffic::testing::point_at(road, 0.0, 0.0));
  const int east = zones.place_of(traffic::testing::point_at(road, 2.0, 0.0));
  std::vector<PlaceRobot> robots{{0, west, east, false}, {0, east, west, false}};
  int steps = 0;
  for (; steps < 200 && (robots[0].place != east || robots[1].place != west); ++steps) {
    const std::vector<int> next = planner.plan(robots);
    ASSERT_EQ(broken_step_rule(zones, robots, next), "") << "step " << steps;
    for (std::size_t i = 0; i < robots.size(); ++i) robots[i].place = next[i];
  }
  EXPECT_EQ(robots[0].place, east);
  EXPECT_EQ(robots[1].place, west);
  EXPECT_LT(steps, 80);
}

// A robot wants into the siding, deeper than the robot standing at its end, which wants out: it
// cannot push that one anywhere, so it backs out of the siding, the other following, steps aside
// and goes in once the other has passed.
TEST(PlacePibt, ARobotGoingIntoASpurBacksOffForOneComingOut) {
  const map::RoadGraph road = traffic::testing::corridor_with_siding();
  const traffic::ConflictZones zones(road, forklift_params());
  PlaceGraph graph(road, zones);
  PlacePibt planner(graph, 2);
  const auto at = [&](double x, double y) { return zones.place_of(traffic::testing::point_at(road, x, y)); };
  const std::vector<int> goals{at(0.5, 0.4), at(0.9, 0.0)};
  std::vector<PlaceRobot> robots{{0, at(0.5, 0.2), goals[0], false}, {0, at(0.5, 0.6), goals[1], false}};
  std::vector<int> reached_at(2, -1);
  for (int step = 0; step < 100 && (reached_at[0] < 0 || reached_at[1] < 0); ++step) {
    const std::vector<int> next = planner.plan(robots);
    ASSERT_EQ(broken_step_rule(zones, robots, next), "") << "step " << step;
    for (std::size_t i = 0; i < robots.size(); ++i) {
      robots[i].place = next[i];
      if (robots[i].place == goals[i] && reached_at[i] < 0) {
        reached_at[i] = step;
        robots[i].goal = -1;
        robots[i].held = true;
      }
    }
  }
  EXPECT_GE(reached_at[0], 0) << "the robot going in never got there";
  EXPECT_GE(reached_at[1], 0) << "the robot coming out never got there";
  EXPECT_LT(reached_at[1], reached_at[0]) << "the robot coming out passes first";
}

// The planner's rules hold whatever the robots do: random goals, and robots held (working or
// delayed) at random steps, on a junction with two ways round and on table_a.
TEST(PlacePibt, RandomGoalsAndHoldsNeverBreakTheRules) {
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const std::vector<std::pair<map::RoadGraph, std::size_t>> cases{{traffic::testing::two_ways_between_junctions(), 3},
                                                                  {site.graph.graph, 8}};
  for (const auto& [road, team] : cases) {
    const traffic::ConflictZones zones(road, forklift_params());
    PlaceGraph graph(road, zones);
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      std::mt19937_64 rng(seed);
      std::uniform_int_distribution<int> any_place(0, graph.place_count() - 1);
      std::vector<PlaceRobot> robots;
      for (int tries = 0; tries < 1000 && robots.size() < team; ++tries) {
        const int place = any_place(rng);
        bool apart = true;
        for (const auto& r : robots) apart = apart && !zones.conflict(r.place, place);
        if (apart) robots.push_back({0, place, any_place(rng), false});
      }
      PlacePibt planner(graph, seed);
      std::size_t goals = 0;
      for (int step = 0; step < 400; ++step) {
        for (auto& r : robots) r.held = std::uniform_real_distribution<double>(0.0, 1.0)(rng) < 0.05;
        const std::vector<int> next = planner.plan(robots);
        ASSERT_EQ(broken_step_rule(zones, robots, next), "") << "seed " << seed << " step " << step;
        for (std::size_t i = 0; i < robots.size(); ++i) {
          robots[i].place = next[i];
          if (robots[i].place == robots[i].goal) {
            ++goals;
            robots[i].goal = any_place(rng);
            planner.reached_goal(static_cast<int>(i));
          }
        }
      }
      EXPECT_GT(goals, 5u) << "seed " << seed;
    }
  }
}

// Eight forklifts on random trips on table_a for ten simulated minutes: every footprint apart,
// nobody stuck, and trips done.
TEST(PlaceSim, EightForkliftsOnTableATripWithoutCollisionOrDeadlock) {
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const traffic::ConflictZones zones(site.graph.graph, forklift_params());
  const auto scenario = traffic::site_scenario(site, zones, 8, site.site.approach_distance);
  PlaceSimParams params;
  params.speed = 0.2;
  params.dwell = 10.0;
  PlaceSim sim(site.graph.graph, zones, params, scenario.goal_points, scenario.start_points);
  const PlaceSimReport& report = sim.run_until(600.0);
  EXPECT_EQ(report.collisions, 0u) << report.first_collision;
  EXPECT_EQ(report.plan_conflicts, 0u) << report.first_plan_conflict;
  EXPECT_EQ(report.wait_cycles, 0u) << report.first_wait_cycle;
  EXPECT_EQ(report.deadlocks, 0u) << (report.stall_notes.empty() ? "" : report.stall_notes.front());
  EXPECT_GT(report.trips, 30u);
}

// The plant's four fleets, two robots each (forklifts, reach trucks, stackers, pickers: bodies
// of 0.65 m to 1.7 m on 0.5 m places), on random trips between its finished-goods, picking and
// expedition places: every footprint apart and every step's rules kept, for every pair of types.
TEST(PlaceSim, ThePlantsFourVehicleTypesKeepTheirBodiesApart) {
  const auto config = config::load_fleet_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  auto site = map::load_site_map(fleet::test::source_dir() + "/maps/plant.yaml");
  std::erase_if(site.site.loading_areas, [](const map::LoadingArea& area) {
    return !area.id.starts_with("FG") && !area.id.starts_with("PK") && !area.id.starts_with("EX");
  });
  const traffic::TrafficConfiguration configuration = traffic::configuration_from(config);
  const traffic::ConflictZones zones(site.graph.graph, configuration.resources);
  ASSERT_EQ(zones.type_count(), 4u);
  PlaceSimParams params;
  params.speed = 1.0;
  params.dwell = 10.0;
  for (int i = 0; i < 8; ++i) params.robot_types.push_back(i % 4);
  const auto scenario = traffic::site_scenario(site, zones, 8, site.site.approach_distance, params.robot_types);
  PlaceSim sim(site.graph.graph, zones, params, scenario.goal_points, scenario.start_points);
  const PlaceSimReport& report = sim.run_until(600.0);
  EXPECT_EQ(report.collisions, 0u) << report.first_collision;
  EXPECT_EQ(report.plan_conflicts, 0u) << report.first_plan_conflict;
  EXPECT_EQ(report.wait_cycles, 0u) << report.first_wait_cycle;
  EXPECT_GT(report.trips, 0u);
}

// Graph points whose places are pairwise apart, taken in a random order: where robots may start.
std::vector<int> points_apart(const map::RoadGraph& road, const traffic::ConflictZones& zones, std::size_t count,
                              std::mt19937_64& rng) {
  std::vector<int> points(road.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = static_cast<int>(i);
  std::shuffle(points.begin(), points.end(), rng);
  std::vector<int> apart;
  for (const int point : points) {
    bool clear = true;
    for (const int other : apart) clear = clear && !zones.conflict(zones.place_of(point), zones.place_of(other));
    if (clear && apart.size() < count) apart.push_back(point);
  }
  return apart;
}

// Robots run late at random (a move in five stops for up to four times the plan step, a move in
// fifty for up to twenty) on small graphs and on table_a: the order of visits keeps every body
// apart and no robot ever waits for one that waits for it, whatever the delays.
TEST(PlaceSim, RandomDelaysNeverCollideNorWaitInACycle) {
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const std::vector<std::pair<map::RoadGraph, std::size_t>> cases{{traffic::testing::corridor_with_siding(), 2},
                                                                  {traffic::testing::two_ways_between_junctions(), 3},
                                                                  {traffic::testing::plus_junction(), 3},
                                                                  {site.graph.graph, 8}};
  const std::vector<std::array<double, 3>> delays{{0.2, 0.0, 2.0}, {0.02, 2.0, 10.0}};
  for (const auto& [road, team] : cases) {
    const traffic::ConflictZones zones(road, forklift_params());
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      std::mt19937_64 rng(seed);
      const std::vector<int> starts = points_apart(road, zones, team, rng);
      std::vector<int> goals(road.points.size());
      for (std::size_t i = 0; i < goals.size(); ++i) goals[i] = static_cast<int>(i);
      PlaceSimParams params;
      params.dwell = 1.0;
      params.seed = seed;
      const auto& delay = delays[seed % delays.size()];
      params.delay_probability = delay[0];
      params.delay_min_s = delay[1];
      params.delay_max_s = delay[2];
      PlaceSim sim(road, zones, params, goals, starts);
      const PlaceSimReport& report = sim.run_until(300.0);
      const std::string run = std::to_string(team) + " robots, seed " + std::to_string(seed);
      EXPECT_EQ(report.collisions, 0u) << run << ": " << report.first_collision;
      EXPECT_EQ(report.plan_conflicts, 0u) << run << ": " << report.first_plan_conflict;
      EXPECT_EQ(report.wait_cycles, 0u) << run << ": " << report.first_wait_cycle;
      EXPECT_GT(report.delays, 0u) << run;
      EXPECT_GT(report.goals_reached, 3u) << run << " moves " << report.moves << " max wait " << report.max_wait_s
                                          << (report.stall_notes.empty() ? "" : report.stall_notes[0]);
    }
  }
}

}  // namespace
}  // namespace fleet::coordination
