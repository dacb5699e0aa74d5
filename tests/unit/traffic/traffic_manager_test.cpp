// The traffic manager on small graphs: head-on meetings, junctions, releases, one-way corridors.
#include "traffic/traffic_manager.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "map/site_map.hpp"
#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_sim.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::GraphBuilder;
using testing::point_at;

SimParams scripted() {
  SimParams p;
  p.random_trips = false;
  p.dwell = 0.5;
  return p;
}

// Steps until every robot is idle or `limit` seconds passed; checks safety on the way.
void run_until_idle(TrafficSim& sim, const std::vector<int>& ids, double limit) {
  while (sim.time() < limit) {
    sim.step();
    ASSERT_EQ(sim.report().invariant_violations, 0u) << sim.report().first_violation;
    ASSERT_EQ(sim.report().collisions, 0u) << sim.report().first_collision;
    if (std::all_of(ids.begin(), ids.end(), [&](int id) { return sim.idle(id); })) return;
  }
}

TEST(TrafficManager, HeadOnInACorridorBothFinish) {
  const auto g = testing::corridor_with_siding();
  const int west = point_at(g, 0.0, 0.0);
  const int east = point_at(g, 2.0, 0.0);
  TrafficSim sim(g, {}, scripted(), {}, {west, east});
  sim.add_goal(1, east);
  sim.add_goal(2, west);
  run_until_idle(sim, {1, 2}, 300.0);
  EXPECT_EQ(sim.goals_reached(1), 1u);
  EXPECT_EQ(sim.goals_reached(2), 1u);
  // They cannot pass in the corridor: one of them used the siding.
  EXPECT_GE(sim.report().sidings, 1u);
  EXPECT_EQ(sim.report().deadlocks, 0u);
}

TEST(TrafficManager, ThreeRobotCycleAtACrossingIsBroken) {
  const auto g = testing::plus_junction();
  const int e = point_at(g, 1.0, 0.0), n = point_at(g, 0.0, 1.0), w = point_at(g, -1.0, 0.0);
  TrafficSim sim(g, {}, scripted(), {}, {e, n, w});
  sim.add_goal(1, n);  // each wants the arm end where the next one stands; the south arm is free
  sim.add_goal(2, w);
  sim.add_goal(3, e);
  run_until_idle(sim, {1, 2, 3}, 600.0);
  for (int id : {1, 2, 3}) EXPECT_EQ(sim.goals_reached(id), 1u) << "robot " << id;
  EXPECT_EQ(sim.report().deadlocks, 0u);
  EXPECT_GE(sim.report().sidings + sim.report().reroutes, 1u);
}

TEST(TrafficManager, CrossingTrafficTakesTurnsAtAJunction) {
  const auto g = testing::plus_junction();
  const int e = point_at(g, 1.0, 0.0), n = point_at(g, 0.0, 1.0), w = point_at(g, -1.0, 0.0),
            s = point_at(g, 0.0, -1.0);
  TrafficSim sim(g, {}, scripted(), {}, {w, s});
  sim.add_goal(1, e);
  sim.add_goal(2, n);
  const int centre = sim.manager().zones().place_of(point_at(g, 0.0, 0.0));
  bool one_waited = false;
  while (sim.time() < 120.0 && !(sim.idle(1) && sim.idle(2))) {
    sim.step();
    ASSERT_EQ(sim.report().invariant_violations, 0u) << sim.report().first_violation;
    const auto h1 = sim.manager().held_places(1);
    const auto h2 = sim.manager().held_places(2);
    ASSERT_FALSE(std::binary_search(h1.begin(), h1.end(), centre) && std::binary_search(h2.begin(), h2.end(), centre));
    for (const auto& grant : sim.last_update().grants) one_waited = one_waited || grant.status == GrantStatus::kWaiting;
  }
  EXPECT_EQ(sim.goals_reached(1), 1u);
  EXPECT_EQ(sim.goals_reached(2), 1u);
  EXPECT_TRUE(one_waited);
  EXPECT_EQ(sim.report().collisions, 0u);
}

TEST(TrafficManager, LostRobotFreesWhatItHolds) {
  const auto g = testing::plus_junction();
  const int e = point_at(g, 1.0, 0.0), n = point_at(g, 0.0, 1.0), w = point_at(g, -1.0, 0.0),
            s = point_at(g, 0.0, -1.0);
  TrafficSim sim(g, {}, scripted(), {}, {w, s});
  sim.add_goal(1, e);
  sim.add_goal(2, n);
  const int centre = sim.manager().zones().place_of(point_at(g, 0.0, 0.0));
  // Robot 1 (first by id) takes the crossing; robot 2 waits for it.
  bool two_waits_for_one = false;
  while (sim.time() < 60.0 && !two_waits_for_one) {
    sim.step();
    const Grant* g2 = grant_of(sim.last_update(), 2);
    two_waits_for_one = g2 && g2->status == GrantStatus::kWaiting &&
                        std::find(g2->blocked_by.begin(), g2->blocked_by.end(), 1) != g2->blocked_by.end();
  }
  ASSERT_TRUE(two_waits_for_one);
  const auto held = sim.manager().held_places(1);
  ASSERT_TRUE(std::binary_search(held.begin(), held.end(), centre));
  sim.remove_robot(1);
  EXPECT_FALSE(sim.manager().has_robot(1));
  EXPECT_TRUE(sim.manager().held_places(1).empty());
  sim.step();
  const auto& events = sim.last_update().events;
  EXPECT_TRUE(std::any_of(events.begin(), events.end(), [](const TrafficEvent& event) {
    return event.kind == TrafficEvent::Kind::kRobotRemoved && event.robot_id == 1;
  }));
  run_until_idle(sim, {2}, 120.0);
  EXPECT_EQ(sim.goals_reached(2), 1u);
}

TEST(TrafficManager, ReleasesByDistanceTravelledBeforeTheNextNode) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 2.0, 0.0);
  TrafficManager m(b.graph());
  ASSERT_EQ(m.submit_route({7, 1, road}, 0.0), SubmitStatus::kAccepted);
  auto r = m.update(0.0);
  ASSERT_GT(r.grants.at(0).granted_index, 2);
  const int first = m.zones().place_of(road[0]);
  // 0.06 m along the first 0.1 m edge: past its midpoint by less than the release margin.
  m.report_progress({7, 1, 0.06, {}}, 0.3);
  m.update(0.3);
  auto held = m.held_places(7);
  EXPECT_TRUE(std::binary_search(held.begin(), held.end(), first));
  m.report_progress({7, 1, 0.08, {}}, 0.4);
  m.update(0.4);
  held = m.held_places(7);
  EXPECT_FALSE(std::binary_search(held.begin(), held.end(), first));
  // Progress on another version is ignored.
  m.report_progress({7, 5, 1.5, {}}, 0.5);
  m.update(0.5);
  held = m.held_places(7);
  EXPECT_TRUE(std::binary_search(held.begin(), held.end(), m.zones().place_of(road[1])));
}

// A loader and the transporter behind it are partners: what one holds keeps the other out of
// nothing, where any other robot would wait.
TEST(TrafficManager, PartnersAreNotKeptOutByWhatTheOtherHolds) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 2.0, 0.0);
  std::map<bool, int> granted;
  for (const bool partnered : {false, true}) {
    TrafficManager m(b.graph());
    // Robot 1 stands at the far end of the road; robot 2 wants to drive the whole road.
    const std::vector<int> end(road.end() - 3, road.end());
    ASSERT_EQ(m.submit_route({1, 1, end}, 0.0), SubmitStatus::kAccepted);
    m.update(0.0);
    if (partnered) m.set_partners({{2, 1}});
    ASSERT_EQ(m.submit_route({2, 1, road}, 0.0), SubmitStatus::kAccepted);
    const auto update = m.update(0.1);
    const Grant* two = grant_of(update, 2);
    ASSERT_NE(two, nullptr);
    const bool kept_out = std::find(two->blocked_by.begin(), two->blocked_by.end(), 1) != two->blocked_by.end();
    EXPECT_EQ(kept_out, !partnered);
    granted[partnered] = two->granted_index;
  }
  EXPECT_GT(granted[true], granted[false]);
}

/// Two-way roads whose entry claims act after 8 s: the setting of the entry-claim tests.
TEST(TrafficManager, ValidatesRoutes) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 1.0, 0.0);
  TrafficManager m(b.graph());
  EXPECT_EQ(m.submit_route({1, 1, {}}, 0.0), SubmitStatus::kInvalid);
  EXPECT_EQ(m.submit_route({1, 1, {road[0], road[2]}}, 0.0), SubmitStatus::kInvalid);  // not an edge
  EXPECT_EQ(m.submit_route({1, 1, {road[0], 999}}, 0.0), SubmitStatus::kInvalid);
  ASSERT_EQ(m.submit_route({1, 2, {road[0], road[1], road[2]}}, 0.0), SubmitStatus::kAccepted);
  EXPECT_EQ(m.submit_route({1, 2, {road[0], road[1]}}, 0.0), SubmitStatus::kStale);
  EXPECT_EQ(m.submit_route({1, 3, {road[8], road[9]}}, 0.0), SubmitStatus::kInvalid);  // not where it is
  EXPECT_EQ(m.submit_route({1, 3, {road[0], road[1]}}, 0.0), SubmitStatus::kAccepted);
  TrafficConfiguration bad;
  bad.lookahead = 0.0;
  EXPECT_THROW(TrafficManager(b.graph(), bad), std::invalid_argument);
}

TEST(TrafficManager, OppositeDirectionWaitsOutsideTheCorridor) {
  const auto g = testing::corridor_with_siding();
  auto line = [&](double x0, double x1) {
    std::vector<int> ids;
    const int steps = static_cast<int>(std::lround(std::abs(x1 - x0) / 0.1));
    for (int k = 0; k <= steps; ++k) ids.push_back(point_at(g, x0 + (x1 > x0 ? 0.1 : -0.1) * k, 0.0));
    return ids;
  };
  // Down the siding, through the junction, east into the corridor to x = 0.8.
  std::vector<int> from_siding;
  for (int k = 6; k >= 0; --k) from_siding.push_back(point_at(g, 0.5, 0.1 * k));
  for (double x : {0.6, 0.7, 0.8}) from_siding.push_back(point_at(g, x, 0.0));

  {  // Same direction as the robot in the corridor: granted.
    TrafficManager m(g);
    ASSERT_EQ(m.submit_route({1, 1, line(1.0, 2.0)}, 0.0), SubmitStatus::kAccepted);
    m.update(0.0);
    std::vector<int> to_06(from_siding.begin(), from_siding.end() - 2);
    ASSERT_EQ(m.submit_route({2, 1, to_06}, 0.0), SubmitStatus::kAccepted);
    const auto r = m.update(0.1);
    EXPECT_EQ(grant_of(r, 2)->granted_index, static_cast<int>(to_06.size()) - 1);
    EXPECT_EQ(grant_of(r, 2)->status, GrantStatus::kMoving);
  }
  {  // Towards a robot that will stand at the corridor's dead end (it may come back): not granted.
    TrafficManager m(g);
    ASSERT_EQ(m.submit_route({1, 1, line(1.3, 2.0)}, 0.0), SubmitStatus::kAccepted);
    m.update(0.0);
    ASSERT_EQ(m.submit_route({2, 1, from_siding}, 0.0), SubmitStatus::kAccepted);
    const auto r = m.update(0.1);
    EXPECT_LT(grant_of(r, 2)->granted_index, 5);
    EXPECT_EQ(grant_of(r, 2)->blocked_by, std::vector<int>{1});
  }
  {  // Against the robot in the corridor: stops on the siding, outside the junction zone.
    TrafficManager m(g);
    ASSERT_EQ(m.submit_route({4, 1, line(1.5, 1.0)}, 0.0), SubmitStatus::kAccepted);
    m.update(0.0);
    ASSERT_EQ(m.submit_route({5, 1, from_siding}, 0.0), SubmitStatus::kAccepted);
    const auto r = m.update(0.1);
    const Grant* g5 = grant_of(r, 5);
    ASSERT_NE(g5, nullptr);
    EXPECT_LT(g5->granted_index, 5);
    EXPECT_TRUE(m.zones().stoppable(m.zones().place_of(from_siding[static_cast<std::size_t>(g5->granted_index)])));
    EXPECT_NE(std::find(g5->blocked_by.begin(), g5->blocked_by.end(), 4), g5->blocked_by.end());
    EXPECT_TRUE(m.check_invariant().empty());
  }
}

/// Robot `id` drives on route `version`, always up to its grant, until it waits or arrives.
Grant drive_until_it_stops(TrafficManager& m, int id, std::uint64_t version, double& now) {
  for (int step = 0; step < 1000; ++step, now += 0.1) {
    const auto r = m.update(now);
    const Grant* g = grant_of(r, id);
    if (g == nullptr) return {};
    if (g->status != GrantStatus::kMoving) return *g;
    m.report_progress({id, version, g->granted_distance, {}}, now);
  }
  return {};
}

TEST(TrafficManager, InAOneWayCorridorRobotsQueueUpToARobotStandingAtItsGoal) {
  // Robot 1 stands at the end of its route in the middle of the straight corridor between the
  // junctions (at work at a loading area). Along a one-way corridor it can only leave ahead, so
  // robot 2 behind it drives in up to it; in a two-way corridor it may come back, and robot 2
  // waits outside.
  const auto g = testing::two_ways_between_junctions();
  for (const bool one_way : {true, false}) {
    SCOPED_TRACE(one_way ? "one-way" : "two-way");
    TrafficConfiguration c;
    c.one_way = one_way;
    TrafficManager m(g, c);
    // The straight corridor's driving direction (either, when both ways are open).
    const auto& successors = m.route_graph().successors[static_cast<std::size_t>(point_at(g, 0.7, 0.0))];
    const bool eastwards = std::find(successors.begin(), successors.end(), point_at(g, 0.8, 0.0)) != successors.end();
    const double ahead = eastwards ? 1.0 : -1.0;
    const double junction_behind = eastwards ? 0.0 : 1.5;
    const int tail_behind = point_at(g, junction_behind - 0.6 * ahead, 0.0);
    const int tail_ahead = point_at(g, junction_behind + 2.1 * ahead, 0.0);
    const int middle = point_at(g, junction_behind + 0.8 * ahead, 0.0);

    const auto to_middle = m.search().shortest(point_at(g, junction_behind, 0.0), middle);
    ASSERT_EQ(m.submit_route({1, 1, to_middle}, 0.0), SubmitStatus::kAccepted);
    double now = 0.0;
    ASSERT_EQ(drive_until_it_stops(m, 1, 1, now).status, GrantStatus::kArrived);

    const auto through = m.search().shortest(tail_behind, tail_ahead);
    ASSERT_TRUE(std::find(through.begin(), through.end(), middle) != through.end()) << "robot 2 drives past robot 1";
    ASSERT_EQ(m.submit_route({2, 1, through}, now), SubmitStatus::kAccepted);
    const Grant waits = drive_until_it_stops(m, 2, 1, now);
    ASSERT_EQ(waits.status, GrantStatus::kWaiting);
    EXPECT_EQ(waits.blocked_by, std::vector<int>{1});
    const auto& at = g.points[static_cast<std::size_t>(through[static_cast<std::size_t>(waits.granted_index)])];
    const double into_corridor = (at.x - junction_behind) * ahead;
    if (one_way) {
      EXPECT_GT(into_corridor, 0.2) << "robot 2 stands at x = " << at.x;
    } else {
      EXPECT_LT(into_corridor, 0.0) << "robot 2 stands at x = " << at.x;
    }
    EXPECT_TRUE(m.check_invariant().empty()) << m.check_invariant();
  }
}

/// Robot `id` followed every 0.05 s for up to `limit` s, driving 0.2 m/s within its grants,
/// until the manager re-routes it.
}  // namespace
}  // namespace fleet::traffic
