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
