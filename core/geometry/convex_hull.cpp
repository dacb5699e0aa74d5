#include "geometry/convex_hull.hpp"

#include <algorithm>

namespace fleet::geometry {

Polygon convex_hull(std::vector<Vec2> points) {
  std::sort(points.begin(), points.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  Polygon hull(2 * points.size());
  std::size_t k = 0;
  for (const Vec2& p : points) {
    while (k >= 2 && cross(hull[k - 1] - hull[k - 2], p - hull[k - 2]) <= 0.0) --k;
    hull[k++] = p;
  }
  const std::size_t lower = k + 1;
  for (auto it = points.rbegin() + 1; it != points.rend(); ++it) {
    while (k >= lower && cross(hull[k - 1] - hull[k - 2], *it - hull[k - 2]) <= 0.0) --k;
    hull[k++] = *it;
  }
  hull.resize(k - 1);
  return hull;
}

}  // namespace fleet::geometry
