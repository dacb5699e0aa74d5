// Two robots can come to stand closer than the places allow: a forklift backs out of a place onto
// the lane a little off where it left it, just ahead of a robot granted up to its old spot. The
// one ahead drives on, away from the one that waits for it, instead of both waiting for good.
#include <gtest/gtest.h>

#include "geometry/polygon.hpp"
#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::GraphBuilder;
using testing::point_at;

TEST(StandingConflict, TheRobotAheadDrivesAwayFromTheOneWaitingForIt) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 10.0, 0.0, 0.5);
  TrafficConfiguration c;
  c.one_way = false;
  c.resources.footprint = {1.0, 0.6};
  c.resources.margin = 0.1;
  TrafficManager m(b.graph(), c);
  // Robot 2 drives along the lane and stands at x = 5 (it drops a pallet beside it); robot 1
  // comes up behind it and waits.
  const std::vector<int> from_three(road.begin() + (point_at(b.graph(), 3.0, 0.0) - road.front()), road.end());
  ASSERT_EQ(m.submit_route({2, 1, from_three}, 0.0), SubmitStatus::kAccepted);
  double t = 0.0;
  UpdateResult r = m.update(t);
  m.report_progress({2, 1, 2.0, {}}, t);
  ASSERT_EQ(m.submit_route({1, 1, road}, 0.0), SubmitStatus::kAccepted);
  for (int i = 0; i < 100; ++i, t += 0.1) {
    r = m.update(t);
    m.report_progress({1, 1, grant_of(r, 1)->granted_distance, {}}, t);
    m.report_progress({2, 1, 2.0, {}}, t);
  }
  ASSERT_EQ(grant_of(r, 1)->status, GrantStatus::kWaiting);
  // Robot 2 backs out of the place onto the lane 0.8 m further back than it left it, within the
  // margin of robot 1's granted places: it stands there, its old route void, and asks to drive on
  // along the lane (what the server does with a route that starts where the robot does not
  // stand).
  m.remove_robot(2, t);
  ASSERT_TRUE(m.hold_body(2, geometry::footprint_polygon({4.2, 0.0, 0.0}, {1.0, 0.6}), t));
  const int from = point_at(b.graph(), 4.0, 0.0);
  const std::vector<int> onward(road.begin() + (from - road.front()), road.end());
  ASSERT_EQ(m.submit_route({2, 2, onward}, t), SubmitStatus::kAccepted);
  double driven = 0.0;
  for (int i = 0; i < 200 && driven < 3.0; ++i, t += 0.1) {
    r = m.update(t);
    const Grant* g2 = grant_of(r, 2);
    ASSERT_NE(g2, nullptr);
    driven = std::min(driven + 0.1, g2->granted_distance);
    m.report_progress({2, 2, driven, {}}, t);
    m.report_progress({1, 1, grant_of(r, 1)->granted_distance, {}}, t);
  }
  EXPECT_GE(driven, 3.0) << "robot 2 never drove on; it waits for " << grant_of(r, 2)->blocked_by.size() << " robots";
}

}  // namespace
}  // namespace fleet::traffic
