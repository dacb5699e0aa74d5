// The plant's jams (fleetctl traffic-eval --site plant --verbose): hand-over points that were not
// merged into one place, and a short one-way link between two junctions with no place a robot
// may wait at, so both junctions and the link were held as one stretch.

#include <gtest/gtest.h>

#include "test_graphs.hpp"
#include "traffic/conflict_zones.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {
namespace {

using testing::GraphBuilder;
using testing::point_at;

ResourceParams reach_truck() {
  ResourceParams params;
  params.footprint = {1.6, 0.9};
  params.margin = 0.10;
  return params;
}

/// A one-way link of `length` metres down x = 0 from the merge M (0, length) to the split S
/// (0, 0): lanes from west and east merge at M, and leave S west and east; 2 m arms, 0.5 m
/// spacing. `both_ways`: every road driven both ways; `crossed`: a lane from the south into S too.
map::RoadGraph link_between_junctions(double length, bool both_ways, bool crossed = false) {
  GraphBuilder b;
  const auto road = [&](double x0, double y0, double x1, double y1) {
    if (both_ways) {
      b.road(x0, y0, x1, y1, 0.5);
    } else {
      b.one_way_road(x0, y0, x1, y1, 0.5);
    }
  };
  road(-2.0, length, 0.0, length);
  road(2.0, length, 0.0, length);
  road(0.0, length, 0.0, 0.0);
  road(0.0, 0.0, -2.0, 0.0);
  road(0.0, 0.0, 2.0, 0.0);
  if (crossed) road(0.0, -2.0, 0.0, 0.0);
  return b.graph();
}

TEST(JunctionLinks, HandOverPointsAFewMicrometresApartAreOnePlace) {
  // OpenDRIVE samples a road's end and the next road's start apart by rounding (about 1e-6 m on
  // the plant); the hand-over edge joins them. As two places the end would count as a branch.
  GraphBuilder b;
  const auto first = b.road(0.0, 0.0, 1.0, 0.0);
  const auto second = b.road(1.0 + 1.2e-6, 0.0, 2.0, 0.0);
  b.link(first.back(), second.front());
  const ConflictZones zones(b.graph());
  EXPECT_EQ(zones.place_of(first.back()), zones.place_of(second.front()));
  EXPECT_FALSE(zones.branch(zones.place_of(first.back())));
  EXPECT_EQ(zones.corridor_count(), 1u);
}

TEST(JunctionLinks, AOneWayLinkBetweenCloseJunctionsHasPlacesToWaitAt) {
  const map::RoadGraph graph = link_between_junctions(3.5, false);
  const ConflictZones zones(graph, reach_truck());
  const int middle = zones.place_of(point_at(graph, 0.0, 2.0));
  // Its region reaches the regions of both junction places...
  EXPECT_TRUE(zones.conflict(middle, zones.place_of(point_at(graph, 0.0, 0.0))));
  EXPECT_TRUE(zones.conflict(middle, zones.place_of(point_at(graph, 0.0, 3.5))));
  // ...but everyone who needs them drives along the link: a robot waiting there blocks no one
  // crossing by another way.
  EXPECT_TRUE(zones.stoppable(middle));
  // With a lane from the south into the split too, robots cross it without driving the link.
  const map::RoadGraph crossed = link_between_junctions(3.5, false, true);
  const ConflictZones crossed_zones(crossed, reach_truck());
  EXPECT_FALSE(crossed_zones.stoppable(crossed_zones.place_of(point_at(crossed, 0.0, 2.0))));
  EXPECT_TRUE(crossed_zones.stoppable(crossed_zones.place_of(point_at(crossed, 0.0, 2.5))));
}

TEST(JunctionLinks, ATwoWayLinkBetweenCloseJunctionsStaysAJunction) {
  // Driven both ways, the junctions' places lie on ways that pass the link by: waiting there
  // would block them.
  const map::RoadGraph graph = link_between_junctions(3.5, true);
  const ConflictZones zones(graph, reach_truck());
  EXPECT_FALSE(zones.stoppable(zones.place_of(point_at(graph, 0.0, 2.0))));
}

TEST(JunctionLinks, ARobotWaitsOnTheLinkInsteadOfHoldingBothJunctions) {
  const map::RoadGraph graph = link_between_junctions(3.5, false);
  TrafficConfiguration configuration;
  configuration.resources = reach_truck();
  configuration.lookahead = 8.0;
  configuration.one_way = false;
  TrafficManager manager(graph, configuration);
  // Robot 1 stands on the east arm just past the split; robot 2 comes from the west arm, over
  // the merge and down the link, to the east arm's end.
  const int east = point_at(graph, 1.0, 0.0);
  ASSERT_EQ(manager.submit_route({1, 1, {east}}, 0.0), SubmitStatus::kAccepted);
  const auto route = manager.search().shortest(point_at(graph, -2.0, 3.5), point_at(graph, 2.0, 0.0));
  ASSERT_FALSE(route.empty());
  ASSERT_EQ(manager.submit_route({2, 1, route}, 0.0), SubmitStatus::kAccepted);
  const UpdateResult result = manager.update(0.05);
  const Grant* grant = nullptr;
  for (const auto& g : result.grants) {
    if (g.robot_id == 2) grant = &g;
  }
  ASSERT_NE(grant, nullptr);
  // Granted over the merge into the link (2 m to the merge, then down), stopped short of the split.
  EXPECT_GT(grant->granted_distance, 2.0 + 0.9);
  EXPECT_LT(grant->granted_distance, 2.0 + 3.5);
  EXPECT_EQ(grant->blocked_by, std::vector<int>{1});
  EXPECT_TRUE(manager.check_invariant().empty());
}

}  // namespace
}  // namespace fleet::traffic
