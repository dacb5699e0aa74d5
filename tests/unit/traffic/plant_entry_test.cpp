// Entering the plant's roads from a place beside them, with the plant's own fleets and lanes.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "config/fleet_config.hpp"
#include "geometry/polygon.hpp"
#include "map/site_map.hpp"
#include "test_grants.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;

geometry::Polygon placed(const geometry::Polygon& footprint, const geometry::Pose2& at) {
  geometry::Polygon out;
  for (const auto& c : footprint) {
    out.push_back({at.x + c.x * std::cos(at.yaw) - c.y * std::sin(at.yaw),
                   at.y + c.x * std::sin(at.yaw) + c.y * std::cos(at.yaw)});
  }
  return out;
}

// Two forklifts at neighbouring packaging places (PK8, PK9), both to leave eastwards along the
// corridor's south lane. The one at PK8 enters first and is granted up to the other's body, which
// reaches onto the lane; the one at PK9 then waited to enter until the first had left, and the
// first waited for its body: both for good. The robot at PK9 enters now, keeping the places under
// its body, and drives off ahead; the first follows.
TEST(PlantEntry, ARobotBesideTheRoadEntersAheadOfARobotThatWaitsForItsBody) {
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  const map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  const TrafficConfiguration configuration = configuration_from(config);
  TrafficManager m(site.graph.graph, configuration);
  const int forklift = 0;
  m.set_robot_type(2, forklift);
  m.set_robot_type(3, forklift);
  const auto& footprint = configuration.resources.vehicle_types[forklift].footprint;
  const auto& lanes = m.route_graph(forklift);
  ASSERT_TRUE(m.hold_body(3, placed(footprint, {22.0, 16.52, 1.5708}), 0.0));

  const auto r2 =
      m.search(forklift).shortest(map::nearest_point(lanes, 19.25, 16.355), map::nearest_point(lanes, 27.25, 16.355));
  ASSERT_GT(r2.size(), 10u);
  ASSERT_EQ(m.submit_route({2, 1, r2}, 0.0), SubmitStatus::kAccepted);
  double t = 0.0, d2 = 0.0;
  constexpr double kStep = 0.05, kSpeed = 1.0;
  bool waits = false;
  for (int i = 0; i < 400 && !waits; ++i, t += kStep) {
    const auto r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    const Grant* g2 = grant_of(r, 2);
    ASSERT_NE(g2, nullptr);
    d2 = std::max(d2, std::min(g2->granted_distance, d2 + kSpeed * kStep));
    m.report_progress({2, 1, d2, {}}, t);
    waits = g2->status == GrantStatus::kWaiting && g2->blocked_by == std::vector<int>{3};
  }
  ASSERT_TRUE(waits) << "robot 2 never waited for the body of robot 3";

  const int entry = map::nearest_point(lanes, 22.0, 16.52);
  const auto r3 = m.search(forklift).shortest(entry, map::nearest_point(lanes, 30.25, 16.355));
  ASSERT_EQ(m.holders_in_conflict(entry, 3), std::vector<int>{2});
  const TrafficManager::Entry way_in = m.entry_for(entry, 3, t);
  EXPECT_TRUE(way_in.blockers.empty());
  ASSERT_TRUE(way_in.as_standing);
  ASSERT_EQ(m.submit_route({3, 1, r3}, t), SubmitStatus::kAccepted);
  double d3 = 0.0;
  const double d2_before = d2;
  for (int i = 0; i < 600; ++i, t += kStep) {
    const auto r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    if (const Grant* g3 = grant_of(r, 3)) d3 = std::max(d3, std::min(g3->granted_distance, d3 + kSpeed * kStep));
    if (const Grant* g2 = grant_of(r, 2)) d2 = std::max(d2, std::min(g2->granted_distance, d2 + kSpeed * kStep));
    m.report_progress({3, 1, d3, {}}, t);
    m.report_progress({2, 1, d2, {}}, t);
  }
  EXPECT_GT(d3, 4.0);
  EXPECT_GT(d2, d2_before + 3.0);
}

// Robots that do not wait for it keep it out as before.
TEST(PlantEntry, ARobotDrivingPastKeepsARobotBesideTheRoadOut) {
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  const map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  const TrafficConfiguration configuration = configuration_from(config);
  TrafficManager m(site.graph.graph, configuration);
  const auto& footprint = configuration.resources.vehicle_types[0].footprint;
  const auto& lanes = m.route_graph(0);
  ASSERT_TRUE(m.hold_body(3, placed(footprint, {24.0, 16.52, 1.5708}), 0.0));
  const auto r2 =
      m.search().shortest(map::nearest_point(lanes, 20.25, 16.355), map::nearest_point(lanes, 23.25, 16.355));
  ASSERT_EQ(m.submit_route({2, 1, r2}, 0.0), SubmitStatus::kAccepted);
  m.update(0.0);
  const int entry = map::nearest_point(lanes, 22.25, 16.355);
  const TrafficManager::Entry way_in = m.entry_for(entry, 3, 0.0);
  EXPECT_FALSE(way_in.as_standing);
  EXPECT_EQ(way_in.blockers, std::vector<int>{2});
}

}  // namespace
}  // namespace fleet::traffic
