#pragma once

// Helpers shared by the TrafficManager's source files (private to core/traffic).

#include <algorithm>
#include <limits>
#include <vector>

#include "traffic/conflict_zones.hpp"

namespace fleet::traffic::detail {

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Seconds a robot sent a re-route or a siding gets to act on it before a wait cycle may pick it
// again: the robots around it still see it where it stood until it moves.
inline constexpr double kActOnInstruction = 2.0;

inline void sort_unique(std::vector<int>& ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

// Direction of travel through `places[index]` inside its corridor: towards the next different
// place on the route, 0 when the route leaves the corridor there or ends. Only robots still to
// drive along a corridor claim its direction; one standing at its goal does not.
inline int direction_in(const ConflictZones& zones, const std::vector<int>& places, int index) {
  const int p = places[static_cast<std::size_t>(index)];
  if (zones.corridor(p) < 0) return 0;
  const int n = static_cast<int>(places.size());
  int j = index + 1;
  while (j < n && places[static_cast<std::size_t>(j)] == p) ++j;
  if (j < n) return zones.corridor_direction(p, places[static_cast<std::size_t>(j)]);
  return 0;
}

}  // namespace fleet::traffic::detail
