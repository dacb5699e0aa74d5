#pragma once

#include "traffic/conflict_zones.hpp"

namespace fleet::coordination::testing {

/// Places sized for the tables' forklift (0.25 m by 0.16 m), the one vehicle type.
inline traffic::ResourceParams forklift_params() {
  traffic::ResourceParams params;
  params.footprint = {0.25, 0.16};
  return params;
}

}  // namespace fleet::coordination::testing
