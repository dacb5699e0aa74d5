// The traffic manager letting robots onto the roads: entry claims, standing and frozen bodies.
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

}  // namespace
}  // namespace fleet::traffic
