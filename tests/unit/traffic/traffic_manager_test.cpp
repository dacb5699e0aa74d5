#include "traffic/traffic_manager.hpp"

#include <gtest/gtest.h>

#include <algorithm>

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

/// Two-way roads whose entry claims act after 8 s: the setting of the entry-claim tests.
TrafficConfiguration entry_claims_after_8s() {
  TrafficConfiguration c;
  c.priority_wait = 8.0;
  c.one_way = false;
  return c;
}

TEST(TrafficManager, EntryClaimClosesTheEntryToNewcomersButLetsRobotsInsideDriveOut) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 3.0, 0.0);
  TrafficManager m(b.graph(), entry_claims_after_8s());
  const int entry = point_at(b.graph(), 1.5, 0.0);
  // Robot 2 stands inside the entry's zone, robot 1 comes from behind; both go to the end.
  std::vector<int> from_inside(road.begin() + (point_at(b.graph(), 1.4, 0.0) - road.front()), road.end());
  std::vector<int> from_behind(road.begin(), road.end());
  ASSERT_EQ(m.submit_route({2, 1, from_inside}, 0.0), SubmitStatus::kAccepted);
  ASSERT_EQ(m.submit_route({1, 1, from_behind}, 0.0), SubmitStatus::kAccepted);
  m.claim_entry(3, entry, 0.0);
  EXPECT_FALSE(m.holders_in_conflict(entry, 3).empty());
  // After priority_wait the claim is active: robot 1 is kept short of the zone, robot 2 leaves it.
  UpdateResult r;
  double progress2 = 0.0;
  for (double t = 8.0; t < 30.0; t += 0.1) {
    m.claim_entry(3, entry, t);
    r = m.update(t);
    const Grant* g2 = grant_of(r, 2);
    ASSERT_NE(g2, nullptr);
    progress2 = std::min(g2->granted_distance, progress2 + 0.02);
    m.report_progress({2, 1, progress2, {}}, t);
    const Grant* g1 = grant_of(r, 1);
    ASSERT_NE(g1, nullptr);
    EXPECT_LT(g1->granted_distance, 1.3) << "robot 1 entered the closed zone at t=" << t;
    m.report_progress({1, 1, g1->granted_distance, {}}, t);
    if (m.holders_in_conflict(entry, 3).empty()) break;
  }
  EXPECT_TRUE(m.holders_in_conflict(entry, 3).empty()) << "robot 2 never left the entry's zone";
  // The entrant enters; robot 1 is free again once it is a robot like the others.
  std::vector<int> entering(road.begin() + (entry - road.front()), road.end());
  ASSERT_EQ(m.submit_route({3, 1, entering}, 31.0), SubmitStatus::kAccepted);
  EXPECT_EQ(m.check_invariant(), "");
}

// The road of the claim tests below: robot 2 stands at 1.7 m, inside the zone of an entry at
// 1.5 m (1.2-1.8 m), on its way east; robot 3 waits beside the road to enter there from t = 0, and
// robot 1 comes from behind once the claim is active. Robot 2 alone would let robot 1 come up to
// 1.3 m; the claim keeps it before 1.2 m.
struct ClaimedRoad {
  GraphBuilder b;
  std::vector<int> road = b.road(0.0, 0.0, 3.0, 0.0);
  TrafficManager m{b.graph(), entry_claims_after_8s()};
  int entry = point_at(b.graph(), 1.5, 0.0);
  std::vector<int> from_inside{road.begin() + (point_at(b.graph(), 1.7, 0.0) - road.front()), road.end()};
  static constexpr double kZoneStart = 1.15;

  ClaimedRoad() { EXPECT_EQ(m.submit_route({2, 1, from_inside}, 0.0), SubmitStatus::kAccepted); }
  // One cycle: robot 3 claims, robot 1 drives to its grant; how far robot 1 got (-1 before it came).
  double step(double t) {
    if (t >= 8.5 && !m.has_robot(1)) {
      EXPECT_EQ(m.submit_route({1, 1, road}, t), SubmitStatus::kAccepted);
    }
    m.claim_entry(3, entry, t);
    const auto r = m.update(t);
    const Grant* g1 = grant_of(r, 1);
    if (g1 == nullptr) return -1.0;
    m.report_progress({1, 1, g1->granted_distance, {}}, t);
    return g1->granted_distance;
  }
};

TEST(TrafficManager, EntryClaimHoldsForAsLongAsTheRobotInItsZoneTakesToDriveOut) {
  ClaimedRoad road;
  // Robot 2 stands still until t = 70 s (its safety check stops it for something off the roads,
  // or it queues behind a robot at work): however long that is, robot 1 stays out of the zone.
  for (double t = 0.0; t < 70.0; t += 0.1) {
    const double reached = road.step(t);
    if (t >= 9.0) {
      ASSERT_GT(reached, 0.5) << "robot 1 did not come";
      ASSERT_LT(reached, ClaimedRoad::kZoneStart) << "robot 1 entered the closed zone ahead of the entrant at t=" << t;
    }
  }
  EXPECT_EQ(road.m.holders_in_conflict(road.entry, 3), std::vector<int>{2});
  // Robot 2 drives on out of the zone, and robot 3 enters first.
  double progress2 = 0.0;
  for (double t = 70.0; t < 100.0 && !road.m.holders_in_conflict(road.entry, 3).empty(); t += 0.1) {
    ASSERT_LT(road.step(t), ClaimedRoad::kZoneStart)
        << "robot 1 entered the closed zone ahead of the entrant at t=" << t;
    progress2 += 0.02;
    road.m.report_progress({2, 1, progress2, {}}, t);
  }
  EXPECT_TRUE(road.m.holders_in_conflict(road.entry, 3).empty()) << "robot 2 never left the entry's zone";
  EXPECT_EQ(road.m.check_invariant(), "");
}

TEST(TrafficManager, ARobotKeptOutByAnEntryClaimWaitsForTheEntrant) {
  // The entrant is off the roads, yet the robot it keeps out waits for it: its grant names it,
  // so who waits for whom can be read down to the robot at the end of the line.
  ClaimedRoad road;
  for (double t = 0.0; t < 12.0; t += 0.1) road.step(t);
  const auto r = road.m.update(12.0);
  const Grant* g1 = grant_of(r, 1);
  ASSERT_NE(g1, nullptr);
  EXPECT_EQ(g1->status, GrantStatus::kWaiting);
  EXPECT_EQ(g1->blocked_by, std::vector<int>{3});
}

TEST(TrafficManager, EntryClaimIsLiftedWhenTheRobotInItsWayWaitsOnIt) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 3.0, 0.0);
  TrafficManager m(b.graph(), entry_claims_after_8s());
  const int entry = point_at(b.graph(), 1.5, 0.0);
  // Robot 2 works beside the road, its body reaching over the entry, when robot 3 comes to enter.
  geometry::Polygon at_work{{1.05, -0.1}, {1.52, -0.1}, {1.52, 0.1}, {1.05, 0.1}};
  ASSERT_TRUE(m.hold_body(2, at_work, 0.0));
  for (int i = 0; i < 100; ++i) {
    m.claim_entry(3, entry, i * 0.1);
    m.update(i * 0.1);
  }
  ASSERT_EQ(m.holders_in_conflict(entry, 3), std::vector<int>{2});
  // Done, it sets off from behind the claimed zone: the claim keeps it out while robot 3 waits for
  // it to leave. The claim is lifted and robot 2 drives off.
  const std::vector<int> leave(road.begin() + (point_at(b.graph(), 1.1, 0.0) - road.front()), road.end());
  ASSERT_EQ(m.submit_route({2, 1, leave}, 10.0), SubmitStatus::kAccepted);
  double reached = 0.0;
  for (int i = 100; i < 130; ++i) {
    m.claim_entry(3, entry, i * 0.1);
    const auto r = m.update(i * 0.1);
    const Grant* g2 = grant_of(r, 2);
    ASSERT_NE(g2, nullptr);
    reached = g2->granted_distance;
    m.report_progress({2, 1, reached, {}}, i * 0.1);
  }
  EXPECT_GT(reached, 0.5) << "robot 2 is kept in the entrant's way by the entrant's claim";
  EXPECT_TRUE(m.holders_in_conflict(entry, 3).empty());
  // The claim keeps its place in line: robot 5, leaving an area beside the entry, defers to it.
  EXPECT_EQ(m.earlier_entry_claims(point_at(b.graph(), 1.6, 0.0), 5, 13.0), std::vector<int>{3});
}

TEST(TrafficManager, RobotsEnteringTheRoadsGoInTheOrderTheyCameUnlessOneStandsInTheOthersWay) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 3.0, 0.0);
  TrafficManager m(b.graph(), entry_claims_after_8s());
  const int home_entry = point_at(b.graph(), 1.5, 0.0);
  const int area_entry = point_at(b.graph(), 1.6, 0.0);
  const int far_entry = point_at(b.graph(), 2.8, 0.0);
  // Robot 1 waits at its home for a robot on the road (2) to clear its entry.
  std::vector<int> through(road.begin() + (point_at(b.graph(), 1.4, 0.0) - road.front()), road.end());
  ASSERT_EQ(m.submit_route({2, 1, through}, 0.0), SubmitStatus::kAccepted);
  m.claim_entry(1, home_entry, 0.0);
  // Before priority_wait nobody defers to the claim.
  EXPECT_TRUE(m.earlier_entry_claims(area_entry, 3, 5.0).empty());
  // Robot 2 has gone; robot 3, done at a loading area beside the entry, would enter next to it.
  ASSERT_TRUE(m.remove_robot(2, 9.0));
  EXPECT_TRUE(m.holders_in_conflict(area_entry, 3).empty());
  EXPECT_EQ(m.earlier_entry_claims(area_entry, 3, 9.0), std::vector<int>{1});
  EXPECT_TRUE(m.earlier_entry_claims(home_entry, 1, 9.0).empty()) << "the older claim waits for no newer one";
  EXPECT_TRUE(m.earlier_entry_claims(far_entry, 3, 9.0).empty()) << "an entry clear of the claim";
  // Once robot 3 has waited longer than robot 1's claim, ...
  m.claim_entry(3, area_entry, 9.0);
  EXPECT_EQ(m.earlier_entry_claims(area_entry, 3, 20.0), std::vector<int>{1});
  // ... and a robot whose body stands in the claimant's way goes first.
  geometry::Polygon body{{1.45, -0.1}, {1.75, -0.1}, {1.75, 0.1}, {1.45, 0.1}};
  ASSERT_TRUE(m.hold_body(3, body, 20.0));
  EXPECT_TRUE(m.earlier_entry_claims(area_entry, 3, 20.0).empty());
}

TEST(TrafficManager, FrozenRobotKeepsThePlacesUnderItsBodyAndIsGrantedNothingMore) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 2.0, 0.0);
  TrafficManager m(b.graph());
  ASSERT_EQ(m.submit_route({4, 1, road}, 0.0), SubmitStatus::kAccepted);
  auto r = m.update(0.0);
  m.report_progress({4, 1, 0.35, {}}, 0.1);
  r = m.update(0.1);
  const std::size_t held_moving = m.held_places(4).size();
  // Lost at 0.35 m, facing along the road.
  ASSERT_TRUE(m.freeze_robot(4, geometry::footprint_polygon({0.35, 0.0, 0.0}, geometry::Footprint{}), 0.2));
  EXPECT_TRUE(m.frozen(4));
  r = m.update(0.2);
  const auto held = m.held_places(4);
  EXPECT_LT(held.size(), held_moving);
  // On the road its body lies in one place's region: it holds that place, next to where it stands.
  ASSERT_EQ(held.size(), 1u);
  EXPECT_LE(std::abs(m.zones().position(held.front()).x - 0.35), 0.05 + 1e-9);
  r = m.update(5.0);
  EXPECT_EQ(m.held_places(4), held);  // nothing more, nothing less, while it is silent
  EXPECT_EQ(m.check_invariant(), "");
  // A robot lost beside the roads holds nothing: it is removed.
  ASSERT_EQ(m.submit_route({5, 1, {point_at(b.graph(), 1.8, 0.0), point_at(b.graph(), 1.9, 0.0)}}, 5.0),
            SubmitStatus::kAccepted);
  ASSERT_TRUE(m.freeze_robot(5, geometry::footprint_polygon({1.8, 1.0, 0.0}, geometry::Footprint{}), 5.1));
  EXPECT_FALSE(m.has_robot(5));
  EXPECT_FALSE(m.freeze_robot(99, {}, 6.0));
}

TEST(TrafficManager, AGrantIntoARobotThatTurnsUpStandingIsPulledBack) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 3.0, 0.0);
  TrafficManager m(b.graph());
  ASSERT_EQ(m.submit_route({1, 2, road}, 0.0), SubmitStatus::kAccepted);
  UpdateResult r = m.update(0.0);
  const double first_grant = grant_of(r, 1)->granted_distance;
  ASSERT_GE(first_grant, 0.6);
  m.report_progress({1, 2, 0.2, {}}, 0.05);
  // Robot 7 turns up standing at 0.9 m, inside what robot 1 was granted (it came back onto the
  // road it stood at): robot 1's grant ends short of it, and no one holds a place in conflict
  // with another's.
  ASSERT_TRUE(m.hold_body(7, geometry::footprint_polygon({0.9, 0.0, 0.0}, geometry::Footprint{}), 0.1));
  EXPECT_EQ(m.check_invariant(), "");
  r = m.update(0.1);
  EXPECT_LT(grant_of(r, 1)->granted_distance, first_grant);
  EXPECT_GE(grant_of(r, 1)->granted_distance, 0.2);
  // Robot 7 drives off along the road; robot 1 follows it past where it stood.
  const std::vector<int> away(road.begin() + (point_at(b.graph(), 0.9, 0.0) - road.front()), road.end());
  ASSERT_EQ(m.submit_route({7, 2, away}, 0.1), SubmitStatus::kAccepted);
  double t = 0.1, d1 = 0.2, d7 = 0.0;
  for (int i = 0; i < 600 && d1 < 1.2; ++i, t += 0.05) {
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    if (const Grant* g7 = grant_of(r, 7)) d7 = std::min(g7->granted_distance, d7 + 0.01);
    if (const Grant* g1 = grant_of(r, 1)) d1 = std::min(g1->granted_distance, d1 + 0.01);
    m.report_progress({7, 2, d7, {}}, t);
    m.report_progress({1, 2, d1, {}}, t);
  }
  EXPECT_GE(d1, 1.2);
}

TEST(TrafficManager, AStandingBodyIsNotDrivenIntoAndEntersWhereItStands) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 3.0, 0.0);
  TrafficManager m(b.graph());
  // Robot 7 stands on the road at 1.5 m without a route (parked there, or not admitted yet).
  const auto body = geometry::footprint_polygon({1.5, 0.0, 0.0}, geometry::Footprint{});
  ASSERT_TRUE(m.hold_body(7, body, 0.0));
  EXPECT_TRUE(m.frozen(7));
  const auto held = m.held_places(7);
  ASSERT_FALSE(held.empty());
  EXPECT_TRUE(std::binary_search(held.begin(), held.end(), m.zones().place_of(point_at(b.graph(), 1.5, 0.0))));
  // Robot 1 drives along the road towards it: it is granted up to the body, never into it.
  ASSERT_EQ(m.submit_route({1, 2, road}, 0.0), SubmitStatus::kAccepted);
  double t = 0.0;
  const Grant* g1 = nullptr;
  UpdateResult r;
  for (int i = 0; i < 200; ++i, t += 0.05) {
    r = m.update(t);
    g1 = grant_of(r, 1);
    ASSERT_NE(g1, nullptr);
    m.report_progress({1, 2, g1->granted_distance, {}}, t);
    ASSERT_EQ(m.check_invariant(), "");
  }
  EXPECT_EQ(g1->status, GrantStatus::kWaiting);
  EXPECT_EQ(g1->blocked_by, std::vector<int>{7});
  EXPECT_LT(g1->granted_distance, 1.5);
  // A second hold of the same body changes nothing; a robot on a route is left alone.
  EXPECT_TRUE(m.hold_body(7, body, t));
  EXPECT_EQ(m.held_places(7), held);
  EXPECT_FALSE(m.hold_body(1, body, t));
  // Robot 7 enters where it stands, with any route version, and drives away; robot 1 follows.
  const std::vector<int> away(road.begin() + (point_at(b.graph(), 1.5, 0.0) - road.front()), road.end());
  ASSERT_EQ(m.submit_route({7, 2, away}, t), SubmitStatus::kAccepted);
  EXPECT_FALSE(m.frozen(7));
  double d7 = 0.0;
  for (int i = 0; i < 400 && !(g1 && g1->status == GrantStatus::kArrived); ++i, t += 0.05) {
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    const Grant* g7 = grant_of(r, 7);
    ASSERT_NE(g7, nullptr);
    d7 = std::min(g7->granted_distance, d7 + 0.05);
    m.report_progress({7, 2, d7, {}}, t);
    g1 = grant_of(r, 1);
    if (g1) m.report_progress({1, 2, std::min(g1->granted_distance, d7 + 1.0), {}}, t);
  }
  EXPECT_GT(grant_of(r, 1)->granted_distance, 1.5) << "robot 1 never passed where robot 7 stood";
  // Parked clear of the road, a robot holds nothing and is not kept.
  EXPECT_FALSE(m.hold_body(8, geometry::footprint_polygon({1.5, 2.0, 0.0}, geometry::Footprint{}), t));
  EXPECT_FALSE(m.has_robot(8));
}

TEST(TrafficManager, ARobotStoppedByAnotherBodyClosesACycleAndTheRobotInTheWayBacksOff) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 3.0, 0.0);
  TrafficConfiguration c;
  c.one_way = false;
  TrafficManager m(b.graph(), c);
  // Robot 2 entered at 1.5 m heading east; robot 1 comes up behind it and is granted up to where
  // robot 2's place allows, short of 1.5 m.
  const int entry = point_at(b.graph(), 1.5, 0.0);
  const std::vector<int> onward(road.begin() + (entry - road.front()), road.end());
  ASSERT_EQ(m.submit_route({2, 1, onward}, 0.0), SubmitStatus::kAccepted);
  ASSERT_EQ(m.submit_route({1, 1, road}, 0.0), SubmitStatus::kAccepted);
  double t = 0.0;
  UpdateResult r;
  for (int i = 0; i < 60; ++i, t += 0.05) {
    r = m.update(t);
    m.report_progress({1, 1, grant_of(r, 1)->granted_distance, {}}, t);
    m.report_progress({2, 1, 0.0, {}}, t);
  }
  ASSERT_EQ(grant_of(r, 1)->status, GrantStatus::kWaiting);
  ASSERT_EQ(grant_of(r, 1)->blocked_by, std::vector<int>{2});
  const std::vector<int> robot1_held = m.held_places(1);
  // Robot 2 has not moved: its own safety check stops it for robot 1's body (it turns onto the
  // road across robot 1's path). The grants alone show robot 1 waiting, nobody waiting for it.
  EXPECT_EQ(grant_of(r, 2)->status, GrantStatus::kMoving);
  bool sided = false;
  for (int i = 0; i < 10 && !sided; ++i, t += 0.05) {
    m.report_progress({2, 1, 0.0, {1}}, t);
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    sided = std::any_of(r.events.begin(), r.events.end(),
                        [](const TrafficEvent& e) { return e.kind == TrafficEvent::Kind::kSidingSent; });
  }
  ASSERT_TRUE(sided) << "the wait cycle through robot 2's safety stop was not broken";
  const Grant* g1 = grant_of(r, 1);
  ASSERT_EQ(g1->instruction, Instruction::kSiding);
  ASSERT_GE(g1->route.size(), 2u);
  // Robot 1 backs off a body length at least: its siding is clear of where it stood.
  const int siding = m.zones().place_of(g1->route.back());
  for (int p : robot1_held) EXPECT_FALSE(m.zones().conflict(siding, p)) << "siding place " << siding;
  EXPECT_LT(m.zones().position(siding).x, m.zones().position(robot1_held.front()).x);
  EXPECT_EQ(grant_of(r, 2)->status, GrantStatus::kWaiting);
}

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
struct RerouteWatch {
  double at = -1.0;             ///< when it was re-routed; negative: not within the limit
  double max_wait = 0.0;        ///< longest `waited_s` its grants showed
  Grant grant;                  ///< the re-routing grant, or the last one
  std::vector<int> went_round;  ///< whom the re-route event names
};
RerouteWatch follow_until_rerouted(TrafficManager& m, int id, double limit) {
  RerouteWatch watch;
  double now = 0.0;
  double distance = 0.0;
  while (now < limit) {
    now += 0.05;
    const UpdateResult r = m.update(now);
    watch.grant = *grant_of(r, id);
    watch.max_wait = std::max(watch.max_wait, watch.grant.waited_s);
    if (watch.grant.instruction == Instruction::kReroute) {
      watch.at = now;
      for (const auto& e : r.events) {
        if (e.kind == TrafficEvent::Kind::kRerouted && e.robot_id == id) watch.went_round = e.others;
      }
      break;
    }
    distance = std::min(distance + 0.01, watch.grant.granted_distance);
    m.report_progress({id, watch.grant.version, distance, {}}, now);
  }
  return watch;
}

TEST(TrafficManager, BoundedWaitReroutesAroundARobotThatDoesNotMove) {
  const auto g = testing::two_ways_between_junctions();
  TrafficConfiguration config;
  config.reroute_wait = 10.0;
  config.one_way = false;  // both ways on every road, so the straight way is the shortest
  TrafficManager m(g, config);
  // Robot 1 parks in the middle of the straight way and stays.
  ASSERT_EQ(m.submit_route({1, 1, {point_at(g, 0.8, 0.0)}}, 0.0), SubmitStatus::kAccepted);
  auto path = m.search().shortest(point_at(g, -0.6, 0.0), point_at(g, 2.1, 0.0));
  ASSERT_EQ(m.submit_route({2, 1, path}, 0.0), SubmitStatus::kAccepted);
  const RerouteWatch watch = follow_until_rerouted(m, 2, 40.0);
  ASSERT_GE(watch.at, 0.0);
  EXPECT_LE(watch.max_wait, config.reroute_wait + 0.1);
  EXPECT_EQ(watch.grant.version, 2u);
  EXPECT_EQ(watch.went_round, std::vector<int>{1}) << "the event names the robot it went round";
  // The new route goes round the other way: it never comes near robot 1.
  for (int p : watch.grant.route) {
    for (int q : m.held_places(1)) EXPECT_FALSE(m.zones().conflict(m.zones().place_of(p), q));
  }
  EXPECT_EQ(m.zones().place_of(watch.grant.route.back()), m.zones().place_of(point_at(g, 2.1, 0.0)));
}

/// Both ways on every road; a lost robot is gone round after 3 s, any other after 30 s.
TrafficConfiguration lost_robot_config() {
  TrafficConfiguration config;
  config.reroute_wait = 30.0;
  config.lost_reroute_wait = 3.0;
  config.one_way = false;
  return config;
}

TEST(TrafficManager, ARobotWaitingOnlyOnALostOneIsReroutedWithoutWaitingOutTheBound) {
  // The layout of the test above. Robot 1 drives the straight way and is lost in its middle (a
  // frozen process keeps its body there for as long as it is away); robot 2 behind it goes
  // round after lost_reroute_wait, not after the whole reroute_wait.
  const auto g = testing::two_ways_between_junctions();
  const TrafficConfiguration config = lost_robot_config();
  TrafficManager m(g, config);
  ASSERT_EQ(m.submit_route({1, 1, m.search().shortest(point_at(g, 0.8, 0.0), point_at(g, 2.1, 0.0))}, 0.0),
            SubmitStatus::kAccepted);
  ASSERT_EQ(m.submit_route({2, 1, m.search().shortest(point_at(g, -0.6, 0.0), point_at(g, 2.1, 0.0))}, 0.0),
            SubmitStatus::kAccepted);
  ASSERT_TRUE(m.freeze_robot(1, geometry::footprint_polygon({0.8, 0.0, 0.0}, geometry::Footprint{}), 0.0));
  const RerouteWatch watch = follow_until_rerouted(m, 2, 40.0);
  ASSERT_GT(watch.at, 0.0) << "never re-routed";
  EXPECT_LE(watch.grant.waited_s, config.lost_reroute_wait + 0.1);
  EXPECT_LT(watch.at, config.reroute_wait);
  for (int p : watch.grant.route) {
    for (int q : m.held_places(1)) EXPECT_FALSE(m.zones().conflict(m.zones().place_of(p), q));
  }
  EXPECT_EQ(m.check_invariant(), "");
}

TEST(TrafficManager, ARobotBackFromBeingLostIsWaitedForUpToTheBoundAgain) {
  // Once the lost robot is heard from again (a route from where it stands), robots waiting on it
  // wait for it like for any other robot: up to reroute_wait.
  const auto g = testing::two_ways_between_junctions();
  const TrafficConfiguration config = lost_robot_config();
  TrafficManager m(g, config);
  ASSERT_EQ(m.submit_route({1, 1, {point_at(g, 0.8, 0.0)}}, 0.0), SubmitStatus::kAccepted);
  ASSERT_TRUE(m.freeze_robot(1, geometry::footprint_polygon({0.8, 0.0, 0.0}, geometry::Footprint{}), 0.0));
  ASSERT_EQ(m.submit_route({1, 2, {point_at(g, 0.8, 0.0)}}, 0.0), SubmitStatus::kAccepted);  // back, parked
  ASSERT_EQ(m.submit_route({2, 1, m.search().shortest(point_at(g, -0.6, 0.0), point_at(g, 2.1, 0.0))}, 0.0),
            SubmitStatus::kAccepted);
  const RerouteWatch watch = follow_until_rerouted(m, 2, 20.0);
  EXPECT_LT(watch.at, 0.0) << "re-routed after " << watch.at << " s";
}

// After a server restart two robots stand 0.38 m apart on the east ring of table_a, both to drive
// on southwards. The places under each body must leave the other free to move: were each to hold
// every place its body touches, each would wait for the other for good.
TEST(TrafficManager, RobotsStandingCloseInACorridorBothDriveOnAfterARestart) {
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto& g = site.graph.graph;
  for (int order = 0; order < 2; ++order) {
    TrafficManager m(g);
    const geometry::Pose2 p3{2.55, 2.02, -1.5708}, p1{2.55, 2.40, -1.5708};  // 3 ahead, 1 behind
    ASSERT_TRUE(m.hold_body(3, geometry::footprint_polygon(p3, geometry::Footprint{}), 0.0));
    ASSERT_TRUE(m.hold_body(1, geometry::footprint_polygon(p1, geometry::Footprint{}), 0.0));
    const int s3 = map::nearest_point(g, p3.x, p3.y), s1 = map::nearest_point(g, p1.x, p1.y);
    const auto r3 = m.search().shortest(s3, map::nearest_point(g, 0.97, 2.55));
    const auto r1 = m.search().shortest(s1, map::nearest_point(g, 0.79, 0.45));
    ASSERT_FALSE(r3.empty());
    ASSERT_FALSE(r1.empty());
    if (order == 0) {
      ASSERT_EQ(m.submit_route({3, 2, r3}, 0.0), SubmitStatus::kAccepted);
      ASSERT_EQ(m.submit_route({1, 2, r1}, 0.0), SubmitStatus::kAccepted);
    } else {
      ASSERT_EQ(m.submit_route({1, 2, r1}, 0.0), SubmitStatus::kAccepted);
      ASSERT_EQ(m.submit_route({3, 2, r3}, 0.0), SubmitStatus::kAccepted);
    }
    double t = 0.0, d1 = 0.0, d3 = 0.0;
    for (int i = 0; i < 400; ++i, t += 0.05) {
      const auto r = m.update(t);
      ASSERT_EQ(m.check_invariant(), "");
      if (const Grant* g3 = grant_of(r, 3)) d3 = std::min(g3->granted_distance, d3 + 0.005);
      if (const Grant* g1 = grant_of(r, 1)) d1 = std::min(g1->granted_distance, d1 + 0.005);
      m.report_progress({3, 2, d3, {}}, t);
      m.report_progress({1, 2, d1, {}}, t);
    }
    EXPECT_GT(d3, 0.5) << order;
    EXPECT_GT(d1, 0.5) << order;
  }
}

TEST(TrafficManager, RobotsStandingOneBodyApartAfterARestartDriveOnOneAfterTheOther) {
  // Seen after a server restart in a soak: two robots on the north ring, 0.4 m apart, both
  // driving east. Each body touches several places (no one place's region holds it), and the
  // places ahead of the front robot conflict with places under the rear one's body. The front
  // robot drives on, as its footprint stays clear of the rear body; then the rear one follows.
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto& g = site.graph.graph;
  for (double front_yaw : {1.5708, 0.8, 0.0}) {
    for (double rear_yaw : {0.0, 0.5, 1.0, 1.5708}) {
      TrafficManager m(g);
      const geometry::Pose2 front{1.01, 2.57, front_yaw}, rear{0.61, 2.53, rear_yaw};
      ASSERT_TRUE(m.hold_body(5, geometry::footprint_polygon(front, geometry::Footprint{}), 0.0));
      ASSERT_TRUE(m.hold_body(2, geometry::footprint_polygon(rear, geometry::Footprint{}), 0.0));
      ASSERT_GT(m.held_places(5).size(), 1u);
      ASSERT_EQ(m.check_invariant(), "");
      const auto r5 = m.search().shortest(map::nearest_point(g, 0.97, 2.55), map::nearest_point(g, 2.55, 1.8));
      const auto r2 = m.search().shortest(map::nearest_point(g, rear.x, rear.y), map::nearest_point(g, 2.21, 0.45));
      ASSERT_EQ(m.submit_route({5, 2, r5}, 0.0), SubmitStatus::kAccepted);
      ASSERT_EQ(m.submit_route({2, 2, r2}, 0.0), SubmitStatus::kAccepted);
      double t = 0.0, d5 = 0.0, d2 = 0.0;
      for (int i = 0; i < 400; ++i, t += 0.05) {
        const auto r = m.update(t);
        ASSERT_EQ(m.check_invariant(), "") << front_yaw << " " << rear_yaw;
        if (const Grant* g5 = grant_of(r, 5)) d5 = std::min(g5->granted_distance, d5 + 0.005);
        if (const Grant* g2 = grant_of(r, 2)) d2 = std::min(g2->granted_distance, d2 + 0.005);
        m.report_progress({5, 2, d5, {}}, t);
        m.report_progress({2, 2, d2, {}}, t);
      }
      EXPECT_GT(d5, 1.0) << front_yaw << " " << rear_yaw;
      EXPECT_GT(d2, 0.5) << front_yaw << " " << rear_yaw;
    }
  }
}

// A robot lost on the east ring of table_a while a robot follows it: the follower drives up to
// the lost robot's body; when the lost robot is heard from again, it re-enters from where it
// stands (the points behind it cut off) and drives on ahead, and the follower after it.
TEST(TrafficManager, ARobotBackFromBeingLostDrivesOnAheadOfTheRobotThatCameUpBehindIt) {
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto& g = site.graph.graph;
  for (double lost_at : {0.6, 0.9, 1.2, 1.5, 1.8, 2.1}) {
    TrafficManager m(g);
    const auto& rg = m.route_graph();
    const auto r1 = m.search().shortest(map::nearest_point(rg, 1.6, 2.55), map::nearest_point(rg, 0.79, 0.45));
    const auto r2 = m.search().shortest(map::nearest_point(rg, 0.61, 2.55), map::nearest_point(rg, 2.21, 0.45));
    ASSERT_GT(r1.size(), 2u);
    ASSERT_GT(r2.size(), 2u);
    ASSERT_EQ(m.submit_route({1, 1, r1}, 0.0), SubmitStatus::kAccepted);
    ASSERT_EQ(m.submit_route({2, 1, r2}, 0.0), SubmitStatus::kAccepted);
    const auto pose_along = [&](const std::vector<int>& route, double s) {
      double at = 0.0;
      for (std::size_t k = 1; k < route.size(); ++k) {
        const auto& a = rg.points[static_cast<std::size_t>(route[k - 1])];
        const auto& b = rg.points[static_cast<std::size_t>(route[k])];
        const double len = std::hypot(b.x - a.x, b.y - a.y);
        if (at + len >= s || k + 1 == route.size()) {
          const double u = len > 0.0 ? std::clamp((s - at) / len, 0.0, 1.0) : 0.0;
          return geometry::Pose2{a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), std::atan2(b.y - a.y, b.x - a.x)};
        }
        at += len;
      }
      return geometry::Pose2{};
    };
    double t = 0.0, d1 = 0.0, d2 = 0.0;
    constexpr double kStep = 0.05, kSpeed = 0.5;
    // Both drive until robot 1 is lost_at metres along.
    while (d1 < lost_at && t < 30.0) {
      const auto r = m.update(t);
      if (const Grant* g1 = grant_of(r, 1)) d1 = std::min(g1->granted_distance, d1 + kSpeed * kStep);
      if (const Grant* g2 = grant_of(r, 2)) d2 = std::min(g2->granted_distance, d2 + kSpeed * kStep);
      m.report_progress({1, 1, d1, {}}, t);
      m.report_progress({2, 1, d2, {}}, t);
      t += kStep;
    }
    ASSERT_GE(d1, lost_at);
    const geometry::Pose2 lost_pose = pose_along(r1, d1);
    ASSERT_TRUE(m.freeze_robot(1, geometry::footprint_polygon(lost_pose, geometry::Footprint{}), t));
    for (int i = 0; i < 40; ++i, t += kStep) {  // away 2 s: robot 2 drives up to its body
      const auto r = m.update(t);
      ASSERT_EQ(m.check_invariant(), "");
      if (const Grant* g2 = grant_of(r, 2)) d2 = std::min(g2->granted_distance, d2 + kSpeed * kStep);
      m.report_progress({2, 1, d2, {}}, t);
    }
    // Back: its route from where it stands, as fleet-server enters a returning robot.
    const auto [skip, offset] = m.entry_point(1, r1, d1);
    const std::vector<int> rest(r1.begin() + static_cast<std::ptrdiff_t>(skip), r1.end());
    // fleet-server lets it in where its body holds the route's first place, else once no one
    // holds a place in conflict with that point (TrafficControl).
    bool entered = false;
    const auto try_enter = [&] {
      if (!m.holds_place_of(1, rest.front())) {
        if (!m.holders_in_conflict(rest.front(), 1).empty()) return;
        m.remove_robot(1, t);
      }
      entered = m.submit_route({1, 1, rest}, t) == SubmitStatus::kAccepted;
    };
    double e1 = std::max(d1 - offset, 0.0);
    const double back_at = e1, d2_back = d2;
    for (int i = 0; i < 600; ++i, t += kStep) {
      if (!entered) try_enter();
      const auto r = m.update(t);
      ASSERT_EQ(m.check_invariant(), "");
      const Grant* g1 = entered ? grant_of(r, 1) : nullptr;
      if (g1 != nullptr) e1 = std::min(g1->granted_distance, e1 + kSpeed * kStep);
      if (const Grant* g2 = grant_of(r, 2)) d2 = std::max(d2, std::min(g2->granted_distance, d2 + kSpeed * kStep));
      if (entered) m.report_progress({1, 1, e1, {}}, t);
      m.report_progress({2, 1, d2, {}}, t);
    }
    EXPECT_TRUE(entered) << "lost at " << lost_at;
    EXPECT_GT(e1, back_at + 1.0) << "lost at " << lost_at;
    EXPECT_GT(d2, d2_back + 1.0) << "lost at " << lost_at;
  }
}

}  // namespace
}  // namespace fleet::traffic
