// A robot the traffic manager sends a new route while it waits keeps the places of its old route
// it stands on until it is past the new route's first edge. The places it was granted beyond
// where it stood it may still drive into until it drives the new route; once it reports that
// route, they are free.
#include <gtest/gtest.h>

#include <algorithm>

#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::point_at;

struct Lane {
  map::RoadGraph graph;
  std::vector<int> spur;  ///< south from (4, 1.5) onto the lane
};

// A lane along y = 0 from x = 0 to 6, a way round it south of it from x = 2 to x = 6, a spur
// down onto it at x = 4, and a point off the roads at (3, 0.8).
Lane lane_with_a_way_round() {
  testing::GraphBuilder b;
  Lane l;
  b.road(0.0, 0.0, 6.0, 0.0);
  b.road(2.0, 0.0, 2.0, -1.0);
  b.road(2.0, -1.0, 6.0, -1.0);
  b.road(6.0, -1.0, 6.0, 0.0);
  l.spur = b.road(4.0, 1.5, 4.0, 0.0);
  b.point(3.0, 0.8);
  l.graph = b.graph();
  return l;
}

TrafficConfiguration long_grants() {
  TrafficConfiguration c;
  c.one_way = false;
  c.resources.footprint = {0.3, 0.2};
  c.lookahead = 3.0;  // a long stretch of lane held ahead of a robot
  c.reroute_wait = 1.0;
  return c;
}

std::vector<int> between(const map::RoadGraph& g, double x0, double x1) {
  std::vector<int> points;
  const int n = static_cast<int>(std::lround(std::abs(x1 - x0) / 0.1));
  for (int k = 0; k <= n; ++k) points.push_back(point_at(g, x0 + (x1 > x0 ? 0.1 : -0.1) * k, 0.0));
  return points;
}

bool holds(const TrafficManager& m, int robot, const map::RoadGraph& g, double x) {
  const auto held = m.held_places(robot);
  return std::binary_search(held.begin(), held.end(), m.zones().place_of(point_at(g, x, 0.0)));
}

TEST(RouteChange, TheOldGrantAheadIsFreedOnceTheRobotDrivesTheRouteItWasSent) {
  const Lane l = lane_with_a_way_round();
  TrafficManager m(l.graph, long_grants());
  // Robot 3 stands beside the lane at (3, 0.8).
  ASSERT_EQ(m.submit_route({3, 1, {point_at(l.graph, 3.0, 0.8)}}, 0.0), SubmitStatus::kAccepted);
  // Robot 1 drives east along the lane from x = 1.5 and is granted it well past the spur; at
  // x = 2 its safety check stops it for robot 3's body.
  ASSERT_EQ(m.submit_route({1, 1, between(l.graph, 1.5, 6.0)}, 0.0), SubmitStatus::kAccepted);
  UpdateResult r = m.update(0.0);
  double t = 0.05;
  const Grant* sent = nullptr;
  for (; t < 5.0 && sent == nullptr; t += 0.05) {
    m.report_progress({1, 1, 0.5, {3}}, t);
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    if (grant_of(r, 1)->version == 2) sent = grant_of(r, 1);
  }
  ASSERT_NE(sent, nullptr) << "robot 1 was never sent round robot 3";
  EXPECT_EQ(sent->instruction, Instruction::kReroute);
  // Robot 2 comes down the spur and goes west along the lane robot 1 held, to x = 3.
  std::vector<int> down(l.spur.begin(), l.spur.end());
  const auto west = between(l.graph, 3.9, 3.0);
  down.insert(down.end(), west.begin(), west.end());
  ASSERT_EQ(m.submit_route({2, 1, down}, t), SubmitStatus::kAccepted);
  // Until robot 1 reports the new route it may still be driving the old grant: robot 2 waits.
  for (int i = 0; i < 10; ++i, t += 0.05) {
    m.report_progress({1, 1, 0.5, {3}}, t);
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
  }
  EXPECT_TRUE(holds(m, 1, l.graph, 4.0));
  EXPECT_LT(grant_of(r, 2)->granted_distance, 1.2) << "robot 2 was granted the lane robot 1 may still drive";
  // It reports the new route, standing where it was stopped.
  for (int i = 0; i < 10; ++i, t += 0.05) {
    m.report_progress({1, 2, 0.0, {}}, t);
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
  }
  EXPECT_TRUE(holds(m, 1, l.graph, 2.0)) << "it keeps where it stands";
  EXPECT_FALSE(holds(m, 1, l.graph, 4.0)) << "it keeps the old grant ahead";
  EXPECT_GT(grant_of(r, 2)->granted_distance, 1.6)
      << "robot 2 is not granted the lane; it waits for " << ::testing::PrintToString(grant_of(r, 2)->blocked_by);
}

TEST(RouteChange, ARouteOfTheRobotsOwnKeepsAllItHeldUntilItIsPastTheFirstEdge) {
  const Lane l = lane_with_a_way_round();
  TrafficManager m(l.graph, long_grants());
  ASSERT_EQ(m.submit_route({1, 1, between(l.graph, 1.5, 6.0)}, 0.0), SubmitStatus::kAccepted);
  m.update(0.0);
  m.report_progress({1, 1, 0.5, {}}, 0.1);
  m.update(0.1);
  ASSERT_TRUE(holds(m, 1, l.graph, 4.0));
  // It replans from x = 2 back west: it may have driven on since its last report.
  ASSERT_EQ(m.submit_route({1, 2, between(l.graph, 2.0, 0.5)}, 0.2), SubmitStatus::kAccepted);
  m.report_progress({1, 2, 0.0, {}}, 0.2);
  m.update(0.25);
  EXPECT_TRUE(holds(m, 1, l.graph, 4.0));
  m.report_progress({1, 2, 0.2, {}}, 0.3);
  m.update(0.3);
  EXPECT_FALSE(holds(m, 1, l.graph, 4.0));
}

}  // namespace
}  // namespace fleet::traffic
