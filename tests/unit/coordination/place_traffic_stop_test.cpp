// A robot whose own look-ahead stops it for another robot's body reports it
// (TrafficRoute::stopped_for): the core plans it to stay, drops its visits not yet begun, so that
// robots whose visits wait for them may go first, and names the robot it stops for. A robot the
// plan keeps standing names the robots in its way.
#include <gtest/gtest.h>

#include <vector>

#include "coordination/place_traffic.hpp"
#include "forklift_places.hpp"
#include "geometry/polygon.hpp"

namespace fleet::coordination {
namespace {

using testing::CorridorTraffic;
using testing::Driver;

TEST(PlaceTrafficStop, ARobotStoppedForABodyIsPlannedToStayAndNamesIt) {
  CorridorTraffic corridor;
  auto& [road, zones, search, traffic] = corridor;
  Driver driver = corridor.add_driver(0.0, 2.0);
  ASSERT_FALSE(driver.route.empty());
  // Another robot stands at the siding's end, clear of the corridor as the core sees it.
  const int beside = traffic.add_robot(0);
  traffic.stand(beside, geometry::footprint_polygon({0.5, 0.6, 1.57}, zones.params().footprint));
  double t = 0.0;
  for (; t < 2.0; t += 0.5) driver.cycle(traffic, t);
  ASSERT_GT(driver.x(traffic), 0.1);
  ASSERT_LT(driver.x(traffic), 1.0);

  // Its look-ahead stops it for that body: it stands, planned to stay.
  const double stopped_at = driver.progress;
  for (const double end = t + 10.0; t < end; t += 0.5) {
    traffic.stopped_for(driver.number, {beside});
    traffic.drive(driver.number, driver.version, driver.route, stopped_at);
    traffic.update(t);
  }
  EXPECT_EQ(traffic.places_ahead(driver.number).size(), 1u) << "no visit planned beyond where it stands";
  EXPECT_EQ(traffic.grant(driver.number).waits_for, std::vector<int>{beside}) << "it names whom it stops for";
  EXPECT_LE(traffic.grant(driver.number).granted_distance, stopped_at + 0.1);

  // Its way clear, it drives on to the corridor's end.
  traffic.stopped_for(driver.number, {});
  for (const double end = t + 30.0; t < end; t += 0.5) driver.cycle(traffic, t);
  EXPECT_NEAR(driver.x(traffic), 2.0, 1e-6);
  EXPECT_TRUE(traffic.grant(driver.number).waits_for.empty());
}

TEST(PlaceTrafficStop, ARobotThePlanKeepsStandingNamesTheRobotInItsWay) {
  CorridorTraffic corridor;
  PlaceTraffic& traffic = corridor.traffic;
  // One robot drives into the corridor from its east end and stays at its route's end there, in
  // the way of another driving the corridor's length from the west: nothing pushes a robot at its
  // route's end, so the plan keeps the other standing.
  Driver arriving = corridor.add_driver(2.0, 1.3);
  Driver passing = corridor.add_driver(0.0, 2.0);
  ASSERT_FALSE(arriving.route.empty());
  ASSERT_FALSE(passing.route.empty());
  double t = 0.0;
  for (; t < 30.0; t += 0.5) {
    arriving.cycle(traffic, t);
    passing.cycle(traffic, t);
  }
  ASSERT_TRUE(traffic.grant(arriving.number).arrived);
  EXPECT_LT(passing.x(traffic), 1.3);
  EXPECT_EQ(traffic.grant(passing.number).waits_for, std::vector<int>{arriving.number})
      << "it names the robot whose place its way on conflicts with";
  EXPECT_TRUE(traffic.grant(arriving.number).waits_for.empty());
}

}  // namespace
}  // namespace fleet::coordination
