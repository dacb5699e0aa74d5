// PlaceTraffic on the plant, with the places the server builds (each vehicle type's bodies as its
// own controller sweeps them through the bends).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "config/fleet_config.hpp"
#include "coordination/place_traffic.hpp"
#include "forklift_places.hpp"
#include "geometry/polygon.hpp"
#include "map/road_graph_builder.hpp"
#include "map/site_map.hpp"
#include "robot/robot_factory.hpp"
#include "test_paths.hpp"
#include "traffic/route_search.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::coordination {
namespace {

// A body-frame footprint placed at (x, y) facing `yaw`.
geometry::Polygon placed(const geometry::Polygon& footprint, double x, double y, double yaw) {
  geometry::Polygon body;
  for (const auto& corner : footprint) {
    body.push_back({x + corner.x * std::cos(yaw) - corner.y * std::sin(yaw),
                    y + corner.x * std::sin(yaw) + corner.y * std::cos(yaw)});
  }
  return body;
}

/// The plant's places as the server builds them, and its reach trucks' stalls.
struct PlantTraffic {
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  map::SiteMap site = map::load_site_map(fleet::test::source_dir() + "/maps/plant.yaml");
  traffic::TrafficConfiguration configuration = robot::traffic_configuration_with_drives(config);
  const map::RoadGraph& graph = site.graph.graph;
  traffic::ConflictZones zones{graph, configuration.resources};
  map::RoadGraph lanes = traffic::driving_graph(graph, configuration);
  traffic::RouteSearch search{lanes, zones};
  int reach_truck = configuration.robot_vehicle_types.at("rt1");
  static constexpr std::array<double, 3> kStallX{51.2, 52.4, 53.6};  // PR2, PR1, PR3
  static constexpr double kStallY = 29.1;

  /// The body of a robot of the site's `robot_id` standing at (x, y) facing `yaw`.
  geometry::Polygon body(const std::string& robot_id, double x, double y, double yaw) const {
    geometry::Polygon footprint;
    for (const auto& corner : config.find_robot(robot_id)->first->profile.footprint) footprint.push_back(corner);
    return placed(footprint, x, y, yaw);
  }
  geometry::Polygon parked_body(double x) const {
    return placed(zones.vehicle_types()[static_cast<std::size_t>(reach_truck)].footprint, x, kStallY, -M_PI / 2);
  }
  /// A truck in the stall at `x` with a route out to a place on the road 25 m west.
  testing::Driver leaving(PlaceTraffic& traffic, double x) {
    testing::Driver truck;
    truck.number = traffic.add_robot(reach_truck);
    traffic.stand(truck.number, parked_body(x));
    truck.route = search.shortest(map::nearest_point(graph, x, kStallY), map::nearest_point(graph, 30.0, 25.0));
    return truck;
  }
};

// The reach trucks' stalls PR2, PR1 and PR3 lie 1.2 m apart and join one lane that leads to the
// road by a single stem below PR1. Three trucks given orders at once each want the others' places
// on their way out: the middle one waits until the other two have passed below it, and all three
// reach their goal, 25 m on, within two minutes.
TEST(PlaceTrafficPlant, ReachTrucksLeavingNeighbouringStallsAtOnceAllGetOut) {
  PlantTraffic plant;
  PlaceTraffic traffic(plant.lanes, plant.zones, {.speed = 0.8, .plan_ahead = 4, .seed = 1});
  std::vector<testing::Driver> trucks;
  for (const double x : PlantTraffic::kStallX) {
    trucks.push_back(plant.leaving(traffic, x));
    ASSERT_GE(trucks.back().route.size(), 2u) << "no way from the stall at x " << x;
  }
  for (testing::Driver& truck : trucks) ASSERT_TRUE(traffic.drive(truck.number, truck.version, truck.route, 0.0));
  std::vector<double> out_at(trucks.size(), -1.0);
  for (double t = 0.0; t < 120.0; t += 0.25) {
    for (std::size_t i = 0; i < trucks.size(); ++i) {
      if (out_at[i] >= 0.0) continue;
      trucks[i].cycle(traffic, t);
      if (traffic.grant(trucks[i].number).arrived) {
        out_at[i] = t;
        traffic.stand(trucks[i].number, {});  // it drives on off this part of the site
      }
    }
  }
  for (std::size_t i = 0; i < trucks.size(); ++i) {
    EXPECT_GE(out_at[i], 0.0) << "the truck from the stall at x " << PlantTraffic::kStallX[i]
                              << " never reached its goal";
  }
  EXPECT_TRUE(traffic.wait_cycle().empty());
}

}  // namespace
}  // namespace fleet::coordination
namespace fleet::coordination {
namespace {

// A truck turning from the stem onto the stalls' lane swings over the stalls beside the stem's
// top; one driving straight down from the middle stall does not. Parked trucks in the stalls on
// either side close the stem's top to the first and leave it open to the second: each truck
// leaves its stall, alone, between its parked neighbours.
TEST(PlaceTrafficPlant, EachReachTruckLeavesItsStallBetweenParkedNeighbours) {
  PlantTraffic plant;
  for (const double leaving_x : PlantTraffic::kStallX) {
    PlaceTraffic traffic(plant.lanes, plant.zones, {.speed = 0.8, .plan_ahead = 4, .seed = 1});
    testing::Driver truck;
    for (const double x : PlantTraffic::kStallX) {
      if (x == leaving_x) {
        truck = plant.leaving(traffic, x);
      } else {
        traffic.stand(traffic.add_robot(plant.reach_truck), plant.parked_body(x));
      }
    }
    ASSERT_TRUE(traffic.drive(truck.number, truck.version, truck.route, 0.0));
    double out_at = -1.0;
    for (double t = 0.0; t < 120.0 && out_at < 0.0; t += 0.25) {
      truck.cycle(traffic, t);
      // Its planned moves never sweep into a parked body.
      const std::vector<int> places = traffic.places_ahead(truck.number);
      for (std::size_t k = 1; k < places.size(); ++k) {
        for (const double x : PlantTraffic::kStallX) {
          if (x == leaving_x) continue;
          ASSERT_FALSE(plant.zones.body_reaches_move(plant.parked_body(x), plant.reach_truck, places[k - 1], places[k]))
              << "at " << t << " s the truck from x " << leaving_x << " moves over the truck parked at x " << x;
        }
      }
      if (traffic.grant(truck.number).arrived) out_at = t;
    }
    EXPECT_GE(out_at, 0.0) << "the truck from the stall at x " << leaving_x << " waits for robot "
                           << (traffic.grant(truck.number).waits_for.empty()
                                   ? -1
                                   : traffic.grant(truck.number).waits_for[0]);
  }
}

}  // namespace
}  // namespace fleet::coordination
namespace fleet::coordination {
namespace {

/// A robot's trip through the pick spur: where it starts, then each place it drives to, working
/// 10 s beside the roads at each but the last.
struct SpurTrip {
  const char* robot;
  std::vector<geometry::Vec2> stops;
  bool starts_working = false;  ///< at its first stop, beside the roads
};

/// Drives the trips through PlaceTraffic on the plant for `seconds` as the fleet's robots would
/// (0.8 m/s, their own shortest routes, taking the routes they are handed) and expects every
/// robot done and no wait cycle.
void drive_spur_trips(const std::vector<SpurTrip>& trips, double seconds) {
  PlantTraffic plant;
  PlaceTraffic traffic(plant.lanes, plant.zones, {.speed = 0.8, .plan_ahead = 4, .seed = 1});
  constexpr double kWorkS = 10.0;
  constexpr double kSpeed = 0.8;
  constexpr double kCycleS = 0.25;
  struct State {
    testing::Driver driver;
    std::size_t leg = 0;     // driving from stops[leg] to stops[leg + 1]
    double work_until = -1;  // working beside the roads at stops[leg] until then
    geometry::Polygon body;  // while working or waiting to enter
    bool done = false;
  };
  std::vector<State> robots(trips.size());
  const auto body_at = [&](std::size_t i, geometry::Vec2 at) {
    return plant.body(trips[i].robot, at.x, at.y, -M_PI / 2);  // facing down the spur
  };
  const auto start_leg = [&](std::size_t i) {
    State& r = robots[i];
    const auto& stops = trips[i].stops;
    r.driver.route = plant.search.shortest(map::nearest_point(plant.graph, stops[r.leg].x, stops[r.leg].y),
                                           map::nearest_point(plant.graph, stops[r.leg + 1].x, stops[r.leg + 1].y));
    r.driver.version += 2;  // its own routes take even versions, traffic's odd ones
    r.driver.progress = 0.0;
    if (r.driver.route.size() < 2 || !traffic.drive(r.driver.number, r.driver.version, r.driver.route, 0.0)) {
      return false;
    }
    if (!r.body.empty()) traffic.waiting_body(r.driver.number, r.body);
    return true;
  };
  for (std::size_t i = 0; i < trips.size(); ++i) {
    robots[i].driver.number = traffic.add_robot(plant.configuration.robot_vehicle_types.at(trips[i].robot));
    robots[i].driver.max_step = kSpeed * kCycleS;
    if (trips[i].starts_working) robots[i].body = body_at(i, trips[i].stops[0]);
    ASSERT_TRUE(start_leg(i)) << trips[i].robot;
  }
  for (double t = 0.0; t < seconds; t += kCycleS) {
    for (std::size_t i = 0; i < robots.size(); ++i) {
      State& r = robots[i];
      if (r.done) continue;
      if (r.work_until >= 0.0) {
        if (t < r.work_until) continue;
        r.work_until = -1.0;
        ASSERT_TRUE(start_leg(i)) << trips[i].robot << " leaving its station";
        continue;
      }
      // It drives towards what it is granted at its own speed, and takes the routes it is handed.
      testing::Driver& d = r.driver;
      d.cycle(traffic, t);
      const PlaceGrant& grant = traffic.grant(d.number);
      if (traffic.on_roads(d.number)) r.body.clear();
      if (grant.arrived && grant.version == d.version && d.progress >= grant.granted_distance - 1e-9) {
        ++r.leg;
        if (r.leg + 1 < trips[i].stops.size()) {
          r.body = body_at(i, trips[i].stops[r.leg]);
          traffic.stand(d.number, r.body);
          r.work_until = t + kWorkS;
        } else {
          r.done = true;
          traffic.stand(d.number, {});  // it drives on off this part of the site
        }
      }
    }
  }
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const PlaceGrant& grant = traffic.grant(robots[i].driver.number);
    EXPECT_TRUE(robots[i].done) << trips[i].robot << " on leg " << robots[i].leg
                                << (robots[i].work_until >= 0 ? " working" : "") << ", waiting for robot "
                                << (grant.waits_for.empty() ? -1 : grant.waits_for[0]);
  }
  EXPECT_TRUE(traffic.wait_cycle().empty());
}

// The pick spur west of the racks (x 8, y 2.3 to 5.3) is one lane with a dead end. A picker at its
// end, done at a packing station, leaves for the racks; a forklift has come in behind it for the
// full pallet at the spur's end; a picker stands at the spur's mouth on its way in to a station
// and another comes along the road to one. The forklift backs out of the spur for the picker at
// its end (the picker at the mouth pushed out of its way), and every robot is done within five
// minutes.
TEST(PlaceTrafficPlant, RobotsComingIntoThePickSpurLetTheOneAtItsEndOut) {
  drive_spur_trips({{"pk2", {{8.0, 2.4}, {20.0, 6.12}}, true},
                    {"fk1", {{8.0, 4.6}, {8.0, 2.4}, {30.0, 6.12}}},
                    {"pk3", {{7.72, 6.42}, {8.0, 4.1}, {25.0, 6.12}}},
                    {"pk1", {{8.8, 7.88}, {8.0, 3.2}, {35.0, 6.12}}}},
                   300.0);
}

// A forklift done at PS1, half-way down the spur, leaves for its parking place while another
// forklift comes for the full pallet at PS3, the spur's end, and two pickers come along the road
// behind it for PS2 and PS4: the three coming in make way for the one going out, and every robot
// is done within five minutes.
TEST(PlaceTrafficPlant, ThreeRobotsComingIntoThePickSpurLetOneOutFromItsMiddle) {
  drive_spur_trips({{"fk2", {{8.0, 4.1}, {38.0, 29.1}}, true},
                    {"fk1", {{9.0, 7.88}, {8.0, 2.7}, {30.0, 6.12}}},
                    {"pk2", {{12.0, 7.88}, {8.0, 4.1}, {25.0, 6.12}}},
                    {"pk1", {{15.0, 7.88}, {8.0, 2.7}, {35.0, 6.12}}}},
                   300.0);
}

}  // namespace
}  // namespace fleet::coordination
