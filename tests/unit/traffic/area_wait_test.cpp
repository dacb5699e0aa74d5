// A robot standing beside the roads until its work area is clear (a stacker about to dock) waits
// for the robots in that area. When one of them waits in turn for its standing body, the cycle is
// broken by moving that robot: the standing one is never sent anywhere.
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

TEST(AreaWait, ARobotWaitingForTheBodyOfOneWaitingForItsAreaIsMovedOn) {
  // A 6 m corridor with a 0.6 m siding spur up from x = 2.
  testing::GraphBuilder b;
  b.road(0.0, 0.0, 6.0, 0.0);
  b.road(2.0, 0.0, 2.0, 0.6);
  const auto& g = b.graph();
  TrafficConfiguration c;
  c.one_way = false;
  c.resources.footprint = {0.3, 0.2};
  TrafficManager m(g, c);
  // Robot 2 stands on the corridor at x = 4.5, about to work beside it.
  const geometry::Polygon body{{4.35, -0.1}, {4.65, -0.1}, {4.65, 0.1}, {4.35, 0.1}};
  ASSERT_TRUE(m.hold_body(2, body, 0.0));
  // Robot 1 drives east along the corridor and waits for robot 2's body ...
  std::vector<int> east;
  for (int k = 0; k <= 60; ++k) east.push_back(point_at(g, 0.1 * k, 0.0));
  ASSERT_EQ(m.submit_route({1, 1, east}, 0.0), SubmitStatus::kAccepted);
  double t = 0.0, driven = 0.0;
  UpdateResult r;
  for (int i = 0; i < 400; ++i, t += 0.05) {
    r = m.update(t);
    driven = std::min(driven + 0.02, grant_of(r, 1)->granted_distance);
    m.report_progress({1, 1, driven, {}}, t);
  }
  ASSERT_EQ(grant_of(r, 1)->status, GrantStatus::kWaiting);
  ASSERT_EQ(grant_of(r, 1)->blocked_by, std::vector<int>{2});
  ASSERT_LT(driven, 4.0);
  // ... and stands in the area robot 2 waits to have clear.
  m.wait_for_area(2, {1});
  bool moved_on = false, unresolved = false;
  for (int i = 0; i < 200 && !moved_on; ++i, t += 0.05) {
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    EXPECT_EQ(grant_of(r, 2)->instruction, Instruction::kNone) << "the standing robot was sent off";
    unresolved = unresolved || has_event(r, TrafficEvent::Kind::kUnresolvedDeadlock, 1) ||
                 has_event(r, TrafficEvent::Kind::kUnresolvedDeadlock, 2);
    moved_on = grant_of(r, 1)->instruction != Instruction::kNone;
    m.report_progress({1, 1, driven, {}}, t);
  }
  EXPECT_TRUE(moved_on) << "robot 1 was never moved on" << (unresolved ? " (unresolved deadlock)" : "");
  // Once robot 2's area is clear it waits for no one.
  m.wait_for_area(2, {});
  r = m.update(t);
  EXPECT_TRUE(grant_of(r, 2)->blocked_by.empty());
}

}  // namespace
}  // namespace fleet::traffic
