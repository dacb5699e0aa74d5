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

/// Whether `r` holds an event of `kind` about `robot` (any robot when it is negative).
inline bool has_event(const UpdateResult& r, TrafficEvent::Kind kind, int robot = -1) {
  for (const auto& e : r.events) {
    if (e.kind == kind && (robot < 0 || e.robot_id == robot)) return true;
  }
  return false;
}

}  // namespace fleet::traffic::testing
