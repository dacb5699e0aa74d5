#include "coordination/visit_order.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "../traffic/test_graphs.hpp"
#include "forklift_places.hpp"

namespace fleet::coordination {
namespace {

using testing::forklift_params;

// Two robots on one lane, the second planned to follow the first into the place it leaves: it
// may pass into that place only once the first has left it, however long the first takes.
TEST(VisitOrder, AFollowerPassesIntoAPlaceOnlyOnceTheRobotAheadHasLeftIt) {
  traffic::testing::GraphBuilder b;
  const std::vector<int> lane = b.one_way_road(0.0, 0.0, 2.0, 0.0);
  const traffic::ConflictZones zones(b.graph(), forklift_params());
  const int p4 = zones.place_of(lane[4]);
  const int p8 = zones.place_of(lane[8]);
  const int p12 = zones.place_of(lane[12]);
  VisitOrder order(zones);
  const int behind = order.add_robot(0, p4);
  const int ahead = order.add_robot(0, p8);
  order.plan(ahead, p12, 1);
  order.plan(behind, p8, 1);
  EXPECT_EQ(order.waits_for(behind), ahead);
  EXPECT_THROW(order.leave(behind), std::logic_error);
  EXPECT_EQ(order.waits_for(ahead), -1);
  order.leave(ahead);
  EXPECT_EQ(order.place(ahead), p12);
  EXPECT_EQ(order.waits_for(behind), -1);
  order.arrive(behind);
  EXPECT_EQ(order.current(behind), p8);
  EXPECT_TRUE(order.wait_cycle().empty());
}

// A visit planned at a later step waits for an earlier one of a conflicting place, even when the
// robot of the earlier one has not reached it yet: the order is the plan's, not who comes first.
TEST(VisitOrder, AnEarlierVisitGoesFirstEvenWhenItsRobotRunsLate) {
  const map::RoadGraph road = traffic::testing::plus_junction();
  const traffic::ConflictZones zones(road, forklift_params());
  const int centre = zones.place_of(traffic::testing::point_at(road, 0.0, 0.0));
  VisitOrder order(zones);
  const int west = order.add_robot(0, zones.place_of(traffic::testing::point_at(road, -0.5, 0.0)));
  const int south = order.add_robot(0, zones.place_of(traffic::testing::point_at(road, 0.0, -0.5)));
  // West goes through the centre at steps 1-2 (it is late: it has not moved), south at step 3.
  order.plan(west, zones.place_of(traffic::testing::point_at(road, -0.1, 0.0)), 1);
  order.plan(west, centre, 2);
  order.plan(south, centre, 3);
  EXPECT_EQ(order.waits_for(south), west);
  EXPECT_TRUE(order.wait_cycle().empty());
  EXPECT_THROW(order.plan(south, centre, 3), std::invalid_argument);
}

}  // namespace
}  // namespace fleet::coordination
