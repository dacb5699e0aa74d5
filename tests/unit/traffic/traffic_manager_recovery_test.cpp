// The traffic manager when robots do not move: bounded waits, lost robots, restarts.
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
