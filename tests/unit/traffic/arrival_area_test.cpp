// A long robot turning off its lane into a place beside the road swings across the lane beside
// it: its grant reaches the route's last point only once that area is clear, and the area stays
// closed to others until the robot is back on the road past its next route's first edge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::GraphBuilder;
using testing::point_at;

// Two one-way lanes 2 m apart: eastbound along y = 0, westbound along y = 2. A robot arriving
// eastbound at x = 6 turns south into a place; its turn sweeps up to y = 1.7, into the regions of
// the westbound lane (bodies 0.8 m wide: they reach down to y = 1.585).
const geometry::Polygon kTurn{{5.2, -1.5}, {6.8, -1.5}, {6.8, 1.7}, {5.2, 1.7}};

struct TwoLanes {
  GraphBuilder b;
  std::vector<int> east, west;
  TrafficConfiguration configuration() const {
    TrafficConfiguration c;
    c.resources.footprint = {1.2, 0.8};
    return c;
  }
  TwoLanes() {
    east = b.one_way_road(0.0, 0.0, 10.0, 0.0);
    west = b.one_way_road(10.0, 2.0, 0.0, 2.0);
  }
  std::vector<int> east_until(double x) const { return {east.begin(), east.begin() + std::lround(x / 0.1) + 1}; }
};

// Position along the westbound lane after `progress` metres from x = 10.
double west_x(double progress) {
  return 10.0 - progress;
}

// A loader's picker arrives at its stop beside the pallet of its transporter, whose body is in
// the area its arrival sweeps: partners (set_partners) do not wait for each other there, where
// any other robot would.
TEST(ArrivalArea, APartnerInTheAreaDoesNotHoldTheArrivalUp) {
  std::map<bool, bool> arrived;
  for (const bool partnered : {false, true}) {
    TwoLanes lanes;
    TrafficManager m(lanes.b.graph(), lanes.configuration());
    // Robot 2 stands on the westbound lane beside the turn, holding what its body covers.
    const std::vector<int> standing(lanes.west.begin() + 38, lanes.west.begin() + 44);
    ASSERT_EQ(m.submit_route({2, 1, standing}, 0.0), SubmitStatus::kAccepted);
    if (partnered) m.set_partners({{2, 1}});
    const std::vector<int> in = lanes.east_until(6.0);
    ASSERT_EQ(m.submit_route({1, 2, in}, 0.0), SubmitStatus::kAccepted);
    m.set_arrival_area(1, in.back(), kTurn);
    double east = 0.0;
    for (double t = 0.1; t < 20.0; t += 0.1) {
      const Grant* g1 = grant_of(m.update(t), 1);
      ASSERT_NE(g1, nullptr);
      east = std::min(east + 0.1, g1->granted_distance);
      m.report_progress({1, 2, east, {}}, t);
    }
    arrived[partnered] = m.holds_arrival(1) && std::abs(east - 6.0) < 1e-6;
  }
  EXPECT_FALSE(arrived[false]) << "a robot beside the turn holds it up";
  EXPECT_TRUE(arrived[true]) << "its partner does not";
}

TEST(ArrivalArea, TheLastPointIsGrantedOnlyOnceNobodyDrivesInTheAreaTheTurnSweeps) {
  TwoLanes lanes;
  TrafficManager m(lanes.b.graph(), lanes.configuration());
  const std::vector<int> in = lanes.east_until(6.0);
  ASSERT_EQ(m.submit_route({1, 2, in}, 0.0), SubmitStatus::kAccepted);
  m.set_arrival_area(1, in.back(), kTurn);
  double east = 0.0;
  double west = -1.0;  // robot 2 sets off westbound at t = 2 s, to meet robot 1 at the turn
  bool waited_for_it = false;
  for (double t = 0.1; t < 30.0; t += 0.1) {
    if (west < 0.0 && t >= 2.0) {
      ASSERT_EQ(m.submit_route({2, 2, lanes.west}, t), SubmitStatus::kAccepted);
      west = 0.0;
    }
    const UpdateResult r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "") << "at t = " << t;
    const Grant* g1 = grant_of(r, 1);
    ASSERT_NE(g1, nullptr);
    east = std::min(east + 0.1, g1->granted_distance);
    m.report_progress({1, 2, east, {}}, t);
    if (west >= 0.0) {
      const Grant* g2 = grant_of(r, 2);
      ASSERT_NE(g2, nullptr);
      west = std::min(west + 0.1, g2->granted_distance);
      m.report_progress({2, 2, west, {}}, t);
      const bool in_area = west_x(west) > 5.2 - 0.6 && west_x(west) < 6.8 + 0.6;
      EXPECT_FALSE(in_area && m.holds_arrival(1)) << "robot 1 was let turn in with robot 2 beside it at t = " << t;
      if (g1->status == GrantStatus::kWaiting) {
        waited_for_it =
            waited_for_it || std::find(g1->blocked_by.begin(), g1->blocked_by.end(), 2) != g1->blocked_by.end();
      }
    }
  }
  EXPECT_TRUE(waited_for_it) << "robot 1 never met robot 2 at its turn: the test lost its timing";
  EXPECT_TRUE(m.holds_arrival(1));
  EXPECT_NEAR(east, 6.0, 1e-6) << "robot 1 was never let turn in";
  EXPECT_GT(west, 9.9) << "robot 2 did not drive on";
}

TEST(ArrivalArea, IsClosedToOthersUntilTheRobotIsBackOnTheRoad) {
  TwoLanes lanes;
  TrafficManager m(lanes.b.graph(), lanes.configuration());
  const std::vector<int> in = lanes.east_until(6.0);
  ASSERT_EQ(m.submit_route({1, 2, in}, 0.0), SubmitStatus::kAccepted);
  m.set_arrival_area(1, in.back(), kTurn);
  double east = 0.0;
  for (double t = 0.1; t < 10.0; t += 0.1) {
    const Grant* g = grant_of(m.update(t), 1);
    east = std::min(east + 0.1, g->granted_distance);
    m.report_progress({1, 2, east, {}}, t);
  }
  ASSERT_TRUE(m.holds_arrival(1));
  EXPECT_EQ(m.holders_in_area(3, {{6.0, 1.0}, {6.5, 1.0}, {6.5, 1.5}}), std::vector<int>{1})
      << "a manoeuvre beside the roads into the area waits for it too";
  // Robot 2 comes along the westbound lane while robot 1 works in its place, then backs out: it
  // waits outside the area until robot 1 has left it along a new route.
  ASSERT_EQ(m.submit_route({2, 2, lanes.west}, 10.0), SubmitStatus::kAccepted);
  double west = 0.0;
  double back_out_at = -1.0;
  double out = 0.0;
  const std::vector<int> onward(lanes.east.begin() + 60, lanes.east.end());
  for (double t = 10.1; t < 40.0; t += 0.1) {
    if (back_out_at < 0.0 && t >= 20.0) {
      ASSERT_EQ(m.submit_route({1, 4, onward}, t), SubmitStatus::kAccepted);
      back_out_at = t;
      EXPECT_EQ(m.turn_area(1), kTurn) << "backing out, it sweeps the area it turned in by";
    }
    if (back_out_at >= 0.0 && m.version(1) == 4 && t >= back_out_at + 1.0) {
      // A new plan before it is out (another order came) keeps the area held.
      ASSERT_EQ(m.submit_route({1, 6, onward}, t), SubmitStatus::kAccepted);
    }
    const UpdateResult r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    const Grant* g2 = grant_of(r, 2);
    west = std::min(west + 0.1, g2->granted_distance);
    m.report_progress({2, 2, west, {}}, t);
    if (back_out_at >= 0.0 && t >= back_out_at + 3.0) {  // 3 s backing out before it drives on
      const Grant* g1 = grant_of(r, 1);
      out = std::min(out + 0.1, g1->granted_distance);
      m.report_progress({1, 6, out, {}}, t);
    }
    if (out < 0.05) {
      EXPECT_GT(west_x(west), 6.8) << "robot 2 was granted into the area at t = " << t;
    }
  }
  EXPECT_FALSE(m.holds_arrival(1));
  EXPECT_TRUE(m.turn_area(1).empty()) << "out on the road, it holds its places alone";
  EXPECT_GT(west, 9.9) << "robot 2 never drove on once robot 1 was out";
}

}  // namespace
}  // namespace fleet::traffic
