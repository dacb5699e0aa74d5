// A robot whose own safety check stops it for another robot's body cannot use the road it holds
// beyond where it stands. When that other robot waits for exactly that road, and neither has a
// way round or a siding, the stopped robot gives its road back: the other drives through first.
#include <gtest/gtest.h>

#include <algorithm>

#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::has_event;
using testing::point_at;

TEST(GiveWay, ARobotStoppedByABodyGivesItsRoadToTheRobotWaitingForIt) {
  // One lane driven east from x = 0, and a one-way spur down onto it at x = 0.5: the way a
  // stacker leaves a dock and joins the aisle.
  testing::GraphBuilder b;
  const std::vector<int> lane = b.one_way_road(0.0, 0.0, 4.0, 0.0);
  const std::vector<int> spur = b.one_way_road(0.5, 1.0, 0.5, 0.0);
  const auto& g = b.graph();
  TrafficConfiguration c;
  c.one_way = false;
  c.resources.footprint = {0.3, 0.2};
  c.siding_window = 10.0;  // no place on the lane is off the lane robot's way: no siding
  TrafficManager m(g, c);
  // The joining robot (2) is granted the junction and the lane beyond first.
  std::vector<int> joining(spur.begin(), spur.end());
  joining.insert(joining.end(), lane.begin() + 6, lane.end());
  ASSERT_EQ(m.submit_route({2, 1, joining}, 0.0), SubmitStatus::kAccepted);
  UpdateResult r = m.update(0.0);
  m.report_progress({2, 1, 0.5, {}}, 0.1);
  r = m.update(0.1);
  // The robot on the lane (1) stands at its west end; the joining robot holds the lane ahead of it.
  ASSERT_EQ(m.submit_route({1, 1, lane}, 0.2), SubmitStatus::kAccepted);
  double t = 0.2;
  double driven = 0.0;
  bool lane_robot_passed = false;
  bool unresolved = false;
  for (int i = 0; i < 600 && !lane_robot_passed; ++i, t += 0.05) {
    // The joining robot's safety check stops it for the lane robot's body, wherever it is granted.
    const bool close = driven < 1.0;
    m.report_progress({2, 1, 0.5, close ? std::vector<int>{1} : std::vector<int>{}}, t);
    m.report_progress({1, 1, driven, {}}, t);
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    unresolved = unresolved || has_event(r, TrafficEvent::Kind::kUnresolvedDeadlock);
    driven = std::min(driven + 0.02, grant_of(r, 1)->granted_distance);
    lane_robot_passed = driven > 1.0;
  }
  EXPECT_TRUE(lane_robot_passed) << "the lane robot drove " << driven << " m"
                                 << (unresolved ? " (unresolved deadlock)" : "");
  // Once past, the joining robot is granted its road again.
  for (int i = 0; i < 100; ++i, t += 0.05) {
    m.report_progress({2, 1, 0.5, {}}, t);
    driven = std::min(driven + 0.02, grant_of(r, 1)->granted_distance);
    m.report_progress({1, 1, driven, {}}, t);
    r = m.update(t);
  }
  EXPECT_GT(grant_of(r, 2)->granted_distance, 0.6);
}

}  // namespace
}  // namespace fleet::traffic
