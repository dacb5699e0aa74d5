#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "coordination/place_traffic.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination::testing {

/// Places sized for the tables' forklift (0.25 m by 0.16 m), the one vehicle type.
inline traffic::ResourceParams forklift_params() {
  traffic::ResourceParams params;
  params.footprint = {0.25, 0.16};
  return params;
}

/// A robot on a corridor along x that drives whatever it is granted at once and takes the routes
/// traffic hands it.
struct Driver {
  int number = 0;
  std::uint64_t version = 2;
  std::vector<int> route;
  double progress = 0.0;

  void cycle(PlaceTraffic& traffic, double now) {
    traffic.update(now);
    const PlaceGrant& grant = traffic.grant(number);
    if (grant.version > version && !grant.route.empty()) {
      route = grant.route;  // it begins where the robot stands
      version = grant.version;
      progress = 0.0;
    }
    if (grant.version == version && grant.granted_index >= 0) progress = std::max(progress, grant.granted_distance);
    traffic.drive(number, version, route, progress);
  }
  /// Where its body is along the corridor.
  double x(const PlaceTraffic& traffic) const {
    return traffic.zones().position(traffic.places_ahead(number).front()).x;
  }
};

}  // namespace fleet::coordination::testing
