// Robots entering the roads from beside them: the body that waits to enter and the way out it
// sweeps onto them are held as standing bodies are.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "../traffic/test_graphs.hpp"
#include "coordination/place_traffic.hpp"
#include "forklift_places.hpp"
#include "geometry/polygon.hpp"
#include "traffic/route_search.hpp"

namespace fleet::coordination {
namespace {

using testing::CorridorTraffic;
using testing::Driver;
using testing::forklift_params;
using traffic::testing::point_at;

geometry::Polygon body_at(const traffic::ConflictZones& zones, double x) {
  return geometry::footprint_polygon({x, 0.0, 0.0}, zones.params().footprint);
}

/// The waiter, on the corridor, drives to its end and off it; the driver follows until it is at
/// the end too (or 150 s sim have passed).
void follow_to_the_end(PlaceTraffic& traffic, Driver& waiter, Driver& driver, double& t) {
  bool gone = false;
  for (; t < 150.0 && driver.x(traffic) < 2.0 - 1e-6; t += 0.5) {
    if (!gone) waiter.cycle(traffic, t);
    if (!gone && waiter.x(traffic) >= 2.0 - 1e-6) {
      traffic.stand(waiter.number, {});  // off the corridor's end
      gone = true;
    }
    driver.cycle(traffic, t);
  }
}

// Whether the moves through `places` (from the first, where the robot is) sweep into `body`.
bool moves_reach(const traffic::ConflictZones& zones, const std::vector<int>& places, const geometry::Polygon& body) {
  for (std::size_t k = 1; k < places.size(); ++k) {
    if (zones.body_reaches_move(body, 0, places[k - 1], places[k])) return true;
  }
  return false;
}

// A robot beside the corridor at 1.2 m asks onto it at 1.5 m, where another stands at the
// corridor's end: it waits, and the body it waits with closes what it reaches. A robot driving
// through is held short of it and names it, and follows once it has entered and gone on.
TEST(PlaceTrafficEntry, ARobotWaitingToEnterClosesWhatItsBodyReaches) {
  const map::RoadGraph road = traffic::testing::corridor_with_siding();
  const traffic::ConflictZones zones(road, forklift_params());
  traffic::RouteSearch search(road, zones);
  PlaceTraffic traffic(road, zones, {.plan_period_s = 0.5, .plan_ahead = 2, .seed = 1});
  Driver standing;
  standing.number = traffic.add_robot(0);
  standing.route = {point_at(road, 1.8, 0.0)};
  ASSERT_TRUE(traffic.drive(standing.number, standing.version, standing.route, 0.0));
  Driver waiter;
  waiter.number = traffic.add_robot(0);
  const geometry::Polygon body = body_at(zones, 1.2);
  waiter.route = search.shortest(point_at(road, 1.5, 0.0), point_at(road, 2.0, 0.0));
  ASSERT_TRUE(traffic.drive(waiter.number, waiter.version, waiter.route, 0.0));
  traffic.waiting_body(waiter.number, body);
  Driver driver;
  driver.number = traffic.add_robot(0);
  driver.route = search.shortest(point_at(road, 0.0, 0.0), point_at(road, 2.0, 0.0));
  ASSERT_TRUE(traffic.drive(driver.number, driver.version, driver.route, 0.0));
  double t = 0.0;
  double furthest = 0.0;
  for (; t < 30.0; t += 0.5) {
    driver.cycle(traffic, t);
    furthest = std::max(furthest, driver.x(traffic));
    EXPECT_FALSE(moves_reach(zones, traffic.places_ahead(driver.number), body))
        << "at " << t << " s the driver's moves sweep into the waiting body";
  }
  EXPECT_FALSE(traffic.on_roads(waiter.number));
  EXPECT_EQ(traffic.grant(waiter.number).waits_for, std::vector<int>{standing.number});
  EXPECT_GT(furthest, 0.3);
  EXPECT_EQ(traffic.grant(driver.number).waits_for, std::vector<int>{waiter.number}) << "it names the waiter";

  traffic.stand(standing.number, {});  // it drives off the corridor's end
  follow_to_the_end(traffic, waiter, driver, t);
  EXPECT_NEAR(driver.x(traffic), 2.0, 1e-6) << "the driver follows once the waiter has gone";
}

// A robot stands across the corridor ahead of a driver, closing its way on, and the way out it
// sweeps onto the corridor covers where the driver stands: each waits for the other. The waiter
// pushes the driver back out of its way out, enters, and the driver follows once it has gone.
TEST(PlaceTrafficEntry, ARobotInTheWayOutOfOneItWaitsForIsPushedOutOfIt) {
  CorridorTraffic corridor;
  auto& [road, zones, search, traffic] = corridor;
  Driver driver = corridor.add_driver(1.0, 2.0);
  ASSERT_FALSE(driver.route.empty());
  traffic.update(0.0);
  ASSERT_TRUE(traffic.on_roads(driver.number));

  Driver waiter;
  waiter.number = traffic.add_robot(0);
  waiter.route = search.shortest(point_at(road, 1.5, 0.0), point_at(road, 2.0, 0.0));
  const geometry::Polygon body = body_at(zones, 1.5);
  const geometry::Polygon way_out{{0.8, -0.15}, {1.8, -0.15}, {1.8, 0.15}, {0.8, 0.15}};
  ASSERT_TRUE(traffic.drive(waiter.number, waiter.version, waiter.route, 0.0, way_out));
  traffic.waiting_body(waiter.number, body);
  double t = 0.0;
  for (; t < 60.0 && !traffic.on_roads(waiter.number); t += 0.5) {
    driver.cycle(traffic, t);
    traffic.drive(waiter.number, waiter.version, waiter.route, 0.0, way_out);
  }
  ASSERT_TRUE(traffic.on_roads(waiter.number)) << "the driver was pushed out of the way out";
  EXPECT_LT(driver.x(traffic), 0.8);
  follow_to_the_end(traffic, waiter, driver, t);
  EXPECT_NEAR(driver.x(traffic), 2.0, 1e-6) << "the driver goes on once the waiter has gone";
  EXPECT_TRUE(traffic.wait_cycle().empty());
}

// A robot beside the corridor waits to begin a manoeuvre whose area covers where a driver stands,
// and its body closes the driver's way on: the driver is pushed out of the area, which then
// clears, and no robot outside plans into it meanwhile.
TEST(PlaceTrafficEntry, ARobotWaitingForItsManoeuvresAreaPushesRobotsOutOfIt) {
  CorridorTraffic corridor;
  auto& [road, zones, search, traffic] = corridor;
  Driver driver = corridor.add_driver(1.0, 2.0);
  ASSERT_FALSE(driver.route.empty());
  traffic.update(0.0);
  const int worker = traffic.add_robot(0);
  const geometry::Polygon area{{0.8, -0.15}, {1.8, -0.15}, {1.8, 0.15}, {0.8, 0.15}};
  traffic.stand(worker, body_at(zones, 1.5), area);
  double t = 0.0;
  for (; t < 60.0 && !traffic.robots_in_area(worker, area).empty(); t += 0.5) {
    driver.cycle(traffic, t);
    traffic.stand(worker, body_at(zones, 1.5), area);
  }
  EXPECT_TRUE(traffic.robots_in_area(worker, area).empty()) << "the driver was pushed out of the area";
  EXPECT_LT(t, 10.0) << "pushed at once, not after standing a while";
  for (const double until = t + 10.0; t < until; t += 0.5) {
    driver.cycle(traffic, t);
    EXPECT_TRUE(traffic.robots_in_area(worker, area).empty()) << "at " << t << " s it plans back into the area";
  }
  traffic.stand(worker, {});  // the manoeuvre done, it drives off beside the corridor
  for (; t < 150.0 && driver.x(traffic) < 2.0 - 1e-6; t += 0.5) driver.cycle(traffic, t);
  EXPECT_NEAR(driver.x(traffic), 2.0, 1e-6);
}

}  // namespace
}  // namespace fleet::coordination
