#pragma once

// Reading a TrafficManager's answers in tests.

#include "traffic/traffic_manager.hpp"

namespace fleet::traffic::testing {

/// Robot `id`'s grant in `r`, or nullptr when it got none.
inline const Grant* grant_of(const UpdateResult& r, int id) {
  for (const auto& g : r.grants) {
    if (g.robot_id == id) return &g;
  }
  return nullptr;
}

}  // namespace fleet::traffic::testing
