// A robot whose own safety check stops it for another robot's body cannot use the road it holds
// beyond where it stands. When that other robot waits for exactly that road, and neither has a
// way round or a siding, the stopped robot gives its road back: the other drives through first.
#include <gtest/gtest.h>

#include <algorithm>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "test_grants.hpp"
#include "test_graphs.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_settings.hpp"

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

// Two reach trucks leave neighbouring stalls of the plant's parking street (1.2 m apart) at once.
// The first is granted the street; turning out of its stall it would sweep within its margin of
// the second, which stands in its stall waiting for that street: its safety check stops it for
// that body. Sent to a siding it could not drive either (and each new route restarts its stop's
// report, so the cycle came back every 3 s, for minutes). It gives its road back instead: the
// second drives out first, then the first follows.
TEST(GiveWay, ARobotStoppedInItsStallByItsNeighbourLetsTheNeighbourOutFirst) {
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  const map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  TrafficManager m(site.graph.graph, configuration_from(config));
  const int trucks = vehicle_type_of(config, "reach_trucks");
  m.set_robot_type(1, trucks);
  m.set_robot_type(3, trucks);
  const auto& lanes = m.route_graph(trucks);
  const int goal = map::nearest_point(lanes, 45.0, 24.9);
  const auto first = m.search(trucks).shortest(map::nearest_point(lanes, 52.4, 29.1), goal);
  const auto second = m.search(trucks).shortest(map::nearest_point(lanes, 53.6, 29.1), goal);
  ASSERT_GT(first.size(), 5u);
  ASSERT_GT(second.size(), 5u);
  ASSERT_EQ(m.submit_route({1, 1, first}, 0.0), SubmitStatus::kAccepted);
  UpdateResult r = m.update(0.0);
  ASSERT_EQ(m.submit_route({3, 1, second}, 0.05), SubmitStatus::kAccepted);
  double t = 0.05, d1 = 0.0, d3 = 0.0;
  std::uint64_t v1 = 1, v3 = 1;
  int sidings = 0;
  constexpr double kStep = 0.05, kSpeed = 0.8;
  for (int i = 0; i < 20 * 120 && d1 < 4.0; ++i, t += kStep) {
    r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    sidings += has_event(r, TrafficEvent::Kind::kSidingSent, 1) ? 1 : 0;
    if (const Grant* g = grant_of(r, 1)) {
      if (g->version != v1) d1 = 0.0, v1 = g->version;
      // Stopped by the second truck's body while that one stands within 2 m of its stall.
      if (d3 > 2.0) d1 = std::max(d1, std::min(g->granted_distance, d1 + kSpeed * kStep));
    }
    if (const Grant* g = grant_of(r, 3)) {
      if (g->version != v3) d3 = 0.0, v3 = g->version;
      d3 = std::max(d3, std::min(g->granted_distance, d3 + kSpeed * kStep));
    }
    m.report_progress({1, v1, d1, d3 > 2.0 ? std::vector<int>{} : std::vector<int>{3}}, t);
    m.report_progress({3, v3, d3, {}}, t);
  }
  EXPECT_GT(d3, 2.0) << "the second truck never left its stall";
  EXPECT_GE(d1, 4.0) << "the first truck never followed";
  EXPECT_EQ(sidings, 0) << "the stopped truck was sent to sidings it could not drive to";
}

}  // namespace
}  // namespace fleet::traffic
