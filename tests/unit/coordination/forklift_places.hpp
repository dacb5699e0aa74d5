#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "../traffic/test_graphs.hpp"
#include "coordination/place_traffic.hpp"
#include "traffic/conflict_zones.hpp"
#include "traffic/route_search.hpp"

namespace fleet::coordination::testing {

/// Places sized for the tables' forklift (0.25 m by 0.16 m), the one vehicle type.
inline traffic::ResourceParams forklift_params() {
  traffic::ResourceParams params;
  params.footprint = {0.25, 0.16};
  return params;
}

/// A robot on a corridor along x that drives towards what it is granted (at once, or at most
/// `max_step` metres a cycle) and takes the routes traffic hands it.
struct Driver {
  int number = 0;
  std::uint64_t version = 2;
  std::vector<int> route;
  double progress = 0.0;
  double max_step = std::numeric_limits<double>::infinity();  ///< metres it drives in one cycle at most

  void cycle(PlaceTraffic& traffic, double now) {
    traffic.update(now);
    const PlaceGrant& grant = traffic.grant(number);
    if (grant.version > version && !grant.route.empty()) {
      route = grant.route;  // it begins where the robot stands
      version = grant.version;
      progress = 0.0;
    }
    if (grant.version == version && grant.granted_index >= 0) {
      progress = std::max(progress, std::min(grant.granted_distance, progress + max_step));
    }
    traffic.drive(number, version, route, progress);
  }
  /// Where its body is along the corridor.
  double x(const PlaceTraffic& traffic) const {
    return traffic.zones().position(traffic.places_ahead(number).front()).x;
  }
};

/// PlaceTraffic on the corridor with a siding (traffic::testing::corridor_with_siding), planning
/// every 0.5 s and two moves ahead. Its members bind as `auto& [road, zones, search, traffic]`.
struct CorridorTraffic {
  map::RoadGraph road = traffic::testing::corridor_with_siding();
  traffic::ConflictZones zones{road, forklift_params()};
  traffic::RouteSearch search{road, zones};
  PlaceTraffic traffic{road, zones, {.plan_period_s = 0.5, .plan_ahead = 2, .seed = 1}};

  /// A new robot driving the corridor from x `from` to x `to`, its route handed to traffic (the
  /// route is empty when traffic refused it).
  Driver add_driver(double from, double to) {
    Driver driver;
    driver.number = traffic.add_robot(0);
    driver.route =
        search.shortest(traffic::testing::point_at(road, from, 0.0), traffic::testing::point_at(road, to, 0.0));
    if (!traffic.drive(driver.number, driver.version, driver.route, 0.0)) driver.route.clear();
    return driver;
  }
};

}  // namespace fleet::coordination::testing
