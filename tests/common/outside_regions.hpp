#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::test {

/// How far `point` lies outside every one of `regions`, 0 inside one.
inline double outside(geometry::Vec2 point, const std::vector<const geometry::Polygon*>& regions) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const geometry::Polygon* region : regions) {
    if (geometry::contains(*region, point)) return 0.0;
    for (std::size_t k = 0; k < region->size(); ++k) {
      nearest =
          std::min(nearest, geometry::point_segment_distance(point, (*region)[k], (*region)[(k + 1) % region->size()]));
    }
  }
  return nearest;
}

/// How far the outline of `body` (sampled every tenth of each edge) lies outside `regions`.
inline double outside(const geometry::Polygon& body, const std::vector<const geometry::Polygon*>& regions) {
  double worst = 0.0;
  for (std::size_t k = 0; k < body.size(); ++k) {
    const geometry::Vec2 a = body[k], b = body[(k + 1) % body.size()];
    for (int i = 0; i < 10; ++i) worst = std::max(worst, outside(a + (i / 10.0) * (b - a), regions));
  }
  return worst;
}

}  // namespace fleet::test
