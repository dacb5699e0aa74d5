// A robot whose own look-ahead stops it for another robot's body reports it
// (TrafficRoute::stopped_for): the core plans it to stay, drops its visits not yet begun, so that
// robots whose visits wait for them may go first, and names the robot it stops for.
#include <gtest/gtest.h>

#include <vector>

#include "../traffic/test_graphs.hpp"
#include "coordination/place_traffic.hpp"
#include "forklift_places.hpp"
#include "geometry/polygon.hpp"
#include "traffic/route_search.hpp"

namespace fleet::coordination {
namespace {

using testing::Driver;
using testing::forklift_params;
using traffic::testing::point_at;

TEST(PlaceTrafficStop, ARobotStoppedForABodyIsPlannedToStayAndNamesIt) {
  const map::RoadGraph road = traffic::testing::corridor_with_siding();
  const traffic::ConflictZones zones(road, forklift_params());
  traffic::RouteSearch search(road, zones);
  PlaceTraffic traffic(road, zones, {.plan_period_s = 0.5, .plan_ahead = 2, .seed = 1});
  Driver driver;
  driver.number = traffic.add_robot(0);
  driver.route = search.shortest(point_at(road, 0.0, 0.0), point_at(road, 2.0, 0.0));
  ASSERT_TRUE(traffic.drive(driver.number, driver.version, driver.route, 0.0));
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

}  // namespace
}  // namespace fleet::coordination
