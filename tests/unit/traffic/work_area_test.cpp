// A manoeuvre beside the roads (a stacker docking in reverse) sweeps more than its body: it
// starts only once no other robot holds a place its area touches, and while it holds the area
// nobody is granted into it.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;
using testing::GraphBuilder;
using testing::point_at;

// A 10 m road along y = 0; the area a robot docking at a place beside it, around x = 6, sweeps.
const geometry::Polygon kArea{{5.0, -1.5}, {7.5, -1.5}, {7.5, 0.6}, {5.0, 0.6}};

TEST(WorkArea, IsHeldByWhoeverHoldsAPlaceItTouches) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 10.0, 0.0);
  TrafficManager m(b.graph());
  // Robot 1 drives along the road towards the area; robot 2 stands clear of it.
  const std::vector<int> toward(road.begin(), road.begin() + (point_at(b.graph(), 6.5, 0.0) - road.front()) + 1);
  ASSERT_EQ(m.submit_route({1, 1, toward}, 0.0), SubmitStatus::kAccepted);
  m.update(0.0);
  EXPECT_TRUE(m.holders_in_area(3, kArea).empty()) << "robot 1 holds only the road behind the area so far";
  double progress = 0.0;
  bool entered = false;
  for (double t = 0.1; t < 60.0 && !entered; t += 0.1) {
    const Grant* g = grant_of(m.update(t), 1);
    ASSERT_NE(g, nullptr);
    progress = std::min(progress + 0.1, g->granted_distance);
    m.report_progress({1, 1, progress, {}}, t);
    entered = !m.holders_in_area(3, kArea).empty();
  }
  ASSERT_TRUE(entered) << "robot 1 never reached the area";
  EXPECT_EQ(m.holders_in_area(3, kArea), std::vector<int>{1});
  EXPECT_TRUE(m.holders_in_area(1, kArea).empty()) << "a robot never waits for itself";
}

TEST(WorkArea, IsHeldByARobotParkedBesideTheRoadsWhoseBodyItSweeps) {
  GraphBuilder b;
  b.road(0.0, 0.0, 10.0, 0.0);
  const TrafficManager m(b.graph());
  // Robot 4 parked in a bay beside the road at x = 6 holds no place; robot 5 parked at x = 9.
  const std::map<int, geometry::Polygon> bodies{{4, {{5.8, -1.4}, {6.2, -1.4}, {6.2, -0.9}, {5.8, -0.9}}},
                                                {5, {{8.8, -1.4}, {9.2, -1.4}, {9.2, -0.9}, {8.8, -0.9}}},
                                                {3, {{5.5, -0.5}, {6.5, -0.5}, {6.5, 0.5}, {5.5, 0.5}}}};
  EXPECT_TRUE(m.holders_in_area(3, kArea).empty()) << "nobody holds a place there";
  EXPECT_EQ(m.holders_in_area(3, kArea, bodies), std::vector<int>{4}) << "nor is its own body in its way";
}

TEST(WorkArea, OnceHeldNobodyIsGrantedIntoIt) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 10.0, 0.0);
  TrafficManager m(b.graph());
  ASSERT_TRUE(m.holders_in_area(3, kArea).empty());
  ASSERT_TRUE(m.hold_body(3, kArea, 0.0));
  ASSERT_EQ(m.submit_route({1, 1, road}, 0.0), SubmitStatus::kAccepted);
  double progress = 0.0;
  for (double t = 0.1; t < 60.0; t += 0.1) {
    const Grant* g = grant_of(m.update(t), 1);
    ASSERT_NE(g, nullptr);
    progress = std::min(progress + 0.1, g->granted_distance);
    m.report_progress({1, 1, progress, {}}, t);
  }
  EXPECT_LT(progress, 5.0) << "robot 1 was granted into the held area";
  EXPECT_EQ(m.holders_in_area(1, kArea), std::vector<int>{3});
  EXPECT_EQ(m.check_invariant(), "");
  // The manoeuvre done, the robot stands clear of the road: robot 1 drives through.
  ASSERT_TRUE(m.remove_robot(3, 60.0));
  for (double t = 60.1; t < 120.0; t += 0.1) {
    const Grant* g = grant_of(m.update(t), 1);
    ASSERT_NE(g, nullptr);
    progress = std::min(progress + 0.1, g->granted_distance);
    m.report_progress({1, 1, progress, {}}, t);
  }
  EXPECT_GT(progress, 9.5);
}

TEST(WorkArea, IsNotHeldByTheRegionsOfARobotWaitingForTheOneAskingOnlyByItsBody) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 10.0, 0.0);
  TrafficConfiguration configuration;
  configuration.resources.footprint = {1.0, 0.6};
  TrafficManager m(b.graph(), configuration);
  // Robot 3 stands across the road at x = 6 (about to dock beside it); robot 1 comes along and
  // waits for it, its grant ending short of robot 3's body.
  ASSERT_TRUE(m.hold_body(3, {{5.6, -1.4}, {6.4, -1.4}, {6.4, 0.2}, {5.6, 0.2}}, 0.0));
  ASSERT_EQ(m.submit_route({1, 1, road}, 0.0), SubmitStatus::kAccepted);
  double progress = 0.0;
  for (double t = 0.1; t < 30.0; t += 0.1) {
    const Grant* g = grant_of(m.update(t), 1);
    ASSERT_NE(g, nullptr);
    progress = std::min(progress + 0.1, g->granted_distance);
    m.report_progress({1, 1, progress, {}}, t);
  }
  const Grant* g = grant_of(m.update(30.0), 1);
  ASSERT_EQ(g->status, GrantStatus::kWaiting);
  ASSERT_EQ(g->blocked_by, std::vector<int>{3});
  // Robot 3's docking sweeps up to 3 cm short of robot 1's body: the regions of the places robot
  // 1 holds reach into it, its body does not.
  const double front = progress + 0.5;
  const geometry::Polygon sweep{{front + 0.03, -1.5}, {7.5, -1.5}, {7.5, 0.6}, {front + 0.03, 0.6}};
  const geometry::Polygon body{{progress - 0.5, -0.3}, {front, -0.3}, {front, 0.3}, {progress - 0.5, 0.3}};
  ASSERT_EQ(m.holders_in_area(3, sweep), std::vector<int>{1}) << "the test's sweep misses robot 1's places";
  EXPECT_TRUE(m.holders_in_area(3, sweep, {{1, body}}).empty())
      << "robot 1 waits for robot 3 and stands clear of its sweep";
  const geometry::Polygon over_it{{front - 0.1, -1.5}, {7.5, -1.5}, {7.5, 0.6}, {front - 0.1, 0.6}};
  EXPECT_EQ(m.holders_in_area(3, over_it, {{1, body}}), std::vector<int>{1}) << "a sweep over its body waits for it";
  // Another robot asking for the same sweep, which robot 1 does not wait for, waits for it.
  const std::vector<int> for_another = m.holders_in_area(4, sweep, {{1, body}});
  EXPECT_NE(std::find(for_another.begin(), for_another.end(), 1), for_another.end());
}

// A robot leaving a place beside the road turns out across the lane: it holds that way out before
// it enters (the area of kArea), and it enters as it stands, so the way out stays held until it is
// past its route's first edge. Dropped at the entry, a robot on the road was granted into the way
// out while the leaving robot still turned out across it, and each stood in the other's way.
TEST(WorkArea, AWayOutStaysHeldUntilTheLeavingRobotIsPastItsFirstEdge) {
  GraphBuilder b;
  const auto road = b.road(0.0, 0.0, 10.0, 0.0);
  TrafficManager m(b.graph());
  ASSERT_TRUE(m.hold_body(3, kArea, 0.0));
  ASSERT_EQ(m.submit_route({1, 1, road}, 0.0), SubmitStatus::kAccepted);
  double progress1 = 0.0, t = 0.0;
  const auto drive = [&](double until, double progress3) {
    for (; t < until; t += 0.1) {
      const auto r = m.update(t);
      ASSERT_EQ(m.check_invariant(), "");
      const Grant* g = grant_of(r, 1);
      ASSERT_NE(g, nullptr);
      progress1 = std::min(progress1 + 0.1, g->granted_distance);
      m.report_progress({1, 1, progress1, {}}, t);
      m.report_progress({3, 1, progress3, {}}, t);
    }
  };
  drive(30.0, 0.0);
  ASSERT_LT(progress1, 5.0);
  const int entry = point_at(b.graph(), 6.2, 0.0);
  const TrafficManager::Entry way_in = m.entry_for(entry, 3, t);
  EXPECT_TRUE(way_in.blockers.empty());
  ASSERT_TRUE(way_in.as_standing) << "standing on its entry's place, it enters as it stands";
  const std::vector<int> onward(road.begin() + (entry - road.front()), road.end());
  ASSERT_EQ(m.submit_route({3, 1, onward}, t), SubmitStatus::kAccepted);
  // Turning out, it has not reached the road yet: the way out stays closed to robot 1.
  drive(45.0, 0.0);
  EXPECT_LT(progress1, 5.0) << "robot 1 was granted into the way out of a robot turning out across it";
  EXPECT_EQ(m.holders_in_area(1, kArea), std::vector<int>{3});
  // On the road and past its first edge, it drives off; robot 1 follows through.
  for (double progress3 = 0.1; progress3 < 3.8; progress3 += 0.1) drive(t + 0.1, progress3);
  drive(t + 60.0, 3.8);
  EXPECT_GT(progress1, 7.0);
}

// A stacker docked beside the road at x = 6 will turn out across the road, west or east of where
// it stands, when it leaves. Robot 1 comes along the road: held up by the docked body, it waits
// before the way out, not in it; with the way past free, it drives through.
TEST(WorkArea, NoRobotStopsInTheWayOutOfADockedRobotButOneMayPassThroughIt) {
  GraphBuilder b;
  const auto road = b.one_way_road(0.0, 0.0, 10.0, 0.0);
  b.one_way_road(0.0, 5.0, 10.0, 5.0);
  TrafficConfiguration configuration;
  configuration.resources.footprint = {1.0, 0.6};
  const geometry::Polygon way_out{{3.0, -1.5}, {9.0, -1.5}, {9.0, 0.6}, {3.0, 0.6}};
  const auto drive = [&](TrafficManager& m) {
    double progress = 0.0;
    for (double t = 0.1; t < 30.0; t += 0.1) {
      const UpdateResult r = m.update(t);
      const Grant* g = grant_of(r, 1);
      if (g == nullptr) return -1.0;
      progress = std::min(progress + 0.1, g->granted_distance);
      m.report_progress({1, 1, progress, {}}, t);
      EXPECT_EQ(m.check_invariant(), "");
    }
    return progress;
  };
  const geometry::Polygon across_the_road{{5.6, -1.4}, {6.4, -1.4}, {6.4, 0.2}, {5.6, 0.2}};
  for (const bool keep_clear : {false, true}) {
    TrafficManager m(b.graph(), configuration);
    ASSERT_TRUE(m.hold_body(3, across_the_road, 0.0));
    if (keep_clear) m.keep_clear(3, way_out);
    ASSERT_EQ(m.submit_route({1, 1, road}, 0.0), SubmitStatus::kAccepted);
    const double stood = drive(m);
    ASSERT_GT(stood, 1.0) << "robot 1 never came up";
    if (keep_clear) {
      EXPECT_LT(stood, 3.0) << "robot 1 stopped in the way out of the docked robot";
    } else {
      EXPECT_GT(stood, 3.0) << "without its way out kept, robot 1 drives up to the docked body";
    }
  }
  // Docked by the other road, its way out across this one: robot 1 drives through.
  TrafficManager m(b.graph(), configuration);
  ASSERT_TRUE(m.hold_body(3, {{5.6, 4.6}, {6.4, 4.6}, {6.4, 5.4}, {5.6, 5.4}}, 0.0));
  m.keep_clear(3, way_out);
  ASSERT_EQ(m.submit_route({1, 1, road}, 0.0), SubmitStatus::kAccepted);
  EXPECT_GT(drive(m), 9.5) << "robot 1 was kept from passing the way out";
}

}  // namespace
}  // namespace fleet::traffic
