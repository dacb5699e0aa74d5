#pragma once
// The configuration the roster and command tests share: fleet "forklifts" of two robots, fl1 and
// fl2, 1.0 m long and 0.6 m wide.

#include "config/fleet_config.hpp"

namespace fleet::orders::test {

inline config::FleetConfig two_forklifts() {
  return config::parse_fleet_config(R"(
fleets:
  - id: forklifts
    robot_type: forklift
    profile:
      footprint: {length: 1.0, width: 0.6}
    robots: [{id: fl1, home: H1}, {id: fl2, home: H2}]
)",
                                    "two_forklifts.yaml");
}

}  // namespace fleet::orders::test
