// A robot sent to a siding to make way for another can itself come to wait for that robot (its
// safety check stops it for the other's body before it reaches the siding). The robot it makes
// way for is then in the way and must be the one to move, or both stand for good.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::has_event;
using testing::point_at;

// Two robots driven head-on into a 6 m corridor with a 0.6 m siding spur up from its middle,
// until the manager sends one of them to the siding.
struct HeadOn {
  testing::GraphBuilder b;
  std::unique_ptr<TrafficManager> m;
  double t = 0.0;
  UpdateResult r;
  int yielding = 0;
  std::uint64_t version[3] = {0, 1, 1};
  double driven[3] = {0.0, 0.0, 0.0};

  HeadOn() {
    b.road(0.0, 0.0, 6.0, 0.0);
    b.road(3.0, 0.0, 3.0, 0.6);
    TrafficConfiguration c;
    c.one_way = false;
    m = std::make_unique<TrafficManager>(b.graph(), c);
    std::vector<int> eastward, westward;
    for (int k = 0; k <= 60; ++k) eastward.push_back(point_at(b.graph(), 0.1 * k, 0.0));
    westward.assign(eastward.rbegin(), eastward.rend());
    EXPECT_EQ(m->submit_route({1, 1, eastward}, 0.0), SubmitStatus::kAccepted);
    EXPECT_EQ(m->submit_route({2, 1, westward}, 0.0), SubmitStatus::kAccepted);
    for (int i = 0; i < 600 && yielding == 0; ++i, t += 0.05) {
      r = m->update(t);
      for (int id : {1, 2}) {
        const Grant* grant = grant_of(r, id);
        if (grant->instruction != Instruction::kNone && grant->version != version[id]) {
          version[id] = grant->version;
          driven[id] = 0.0;
        }
        if (has_event(r, TrafficEvent::Kind::kSidingSent, id)) yielding = id;
        driven[id] = std::min(driven[id] + 0.02, grant->granted_distance);
        m->report_progress({id, version[id], driven[id], {}}, t);
      }
    }
  }
};

TEST(SidingYield, TheRobotMadeWayForMovesWhenTheYieldingRobotWaitsForIt) {
  HeadOn h;
  const auto& g = h.b.graph();
  TrafficManager& m = *h.m;
  double& t = h.t;
  UpdateResult& r = h.r;
  const int yielding = h.yielding;
  auto& version = h.version;
  auto& driven = h.driven;
  ASSERT_NE(yielding, 0) << "nobody was sent to the siding";
  const int other = 3 - yielding;
  // They met in the middle: the yielding robot turns into the spur right in front of the other,
  // and its safety check stops it for the other's body; the other waits for its places.
  bool other_moved_off = false;
  bool unresolved = false;
  for (int i = 0; i < 400 && !other_moved_off; ++i, t += 0.05) {
    m.report_progress({yielding, version[yielding], driven[yielding], {other}}, t);
    m.report_progress({other, version[other], driven[other], {}}, t);
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    unresolved = unresolved || has_event(r, TrafficEvent::Kind::kUnresolvedDeadlock, other) ||
                 has_event(r, TrafficEvent::Kind::kUnresolvedDeadlock, yielding);
    const Grant* sent = grant_of(r, other);
    other_moved_off = sent->instruction != Instruction::kNone;
    if (other_moved_off) {
      // It backs away from the spur, the way it came.
      ASSERT_GE(sent->route.size(), 2u);
      const double from = g.points[static_cast<std::size_t>(sent->route.front())].x;
      const double to = g.points[static_cast<std::size_t>(sent->route.back())].x;
      EXPECT_GT(std::abs(to - 3.0), std::abs(from - 3.0));
    }
    if (grant_of(r, yielding)->instruction != Instruction::kNone) version[yielding] = grant_of(r, yielding)->version;
  }
  EXPECT_TRUE(other_moved_off) << "robot " << other << ", which robot " << yielding
                               << " waits for on its way to the siding, was never sent off"
                               << (unresolved ? " (unresolved deadlock)" : "");
}

// Met so close that each one's safety check stops it for the other's body, neither can drive a
// new route that starts towards the other. The one sent away in vain is not sent again and again
// while the other stands: the other is sent off in its turn.
// An agent takes its new route a while after the manager sent it (`ack_lag` seconds: the message
// crosses DDS, the agent plans and reports): a lag longer than the manager waits for a robot to
// act on an instruction must not hand the same robot the next instruction every time.
void expect_both_sent_in_turn(double ack_lag) {
  HeadOn h;
  ASSERT_NE(h.yielding, 0) << "nobody was sent to the siding";
  const int first = h.yielding;
  const int other = 3 - first;
  int first_sent = 0;
  bool other_sent = false;
  std::uint64_t offered[3] = {0, h.version[1], h.version[2]};
  double offered_at[3] = {0.0, 0.0, 0.0};
  for (int i = 0; i < 1200 && !other_sent; ++i, h.t += 0.05) {
    for (int id : {first, other}) {
      if (offered[id] != h.version[id] && h.t - offered_at[id] >= ack_lag) {
        h.version[id] = offered[id];
        h.driven[id] = 0.0;
      }
    }
    h.m->report_progress({first, h.version[first], h.driven[first], {other}}, h.t);
    h.m->report_progress({other, h.version[other], h.driven[other], {first}}, h.t);
    h.r = h.m->update(h.t);
    ASSERT_EQ(h.m->check_invariant(), "");
    for (int id : {first, other}) {
      const Grant* grant = grant_of(h.r, id);
      if (grant->instruction == Instruction::kNone || grant->version == offered[id]) continue;
      offered[id] = grant->version;
      offered_at[id] = h.t;
      if (id == first) ++first_sent;
      other_sent = other_sent || id == other;
    }
  }
  EXPECT_TRUE(other_sent) << "robot " << other << " was never sent off; robot " << first << " was sent " << first_sent
                          << " more times (ack lag " << ack_lag << " s)";
}

TEST(SidingYield, WhenBothStopForTheOtherTheOneSentAwayInVainIsNotTheOnlyOneSent) {
  expect_both_sent_in_turn(0.0);
}

TEST(SidingYield, WhenBothStopForTheOtherTheyAreSentInTurnHoweverLateAgentsTakeTheirRoutes) {
  for (double lag : {1.0, 2.5, 5.0}) expect_both_sent_in_turn(lag);
}

}  // namespace
}  // namespace fleet::traffic
