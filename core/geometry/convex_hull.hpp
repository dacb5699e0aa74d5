#pragma once

#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::geometry {

/// Convex hull (Andrew's monotone chain), counter-clockwise, without collinear points.
Polygon convex_hull(std::vector<Vec2> points);

}  // namespace fleet::geometry
