#include "geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleet::geometry {

Polygon footprint_polygon(const Pose2& pose, const Footprint& footprint, double margin) {
  const double hl = footprint.length / 2.0 + margin;
  const double hw = footprint.width / 2.0 + margin;
  return {body_to_map(pose, {hl, hw}), body_to_map(pose, {-hl, hw}), body_to_map(pose, {-hl, -hw}),
          body_to_map(pose, {hl, -hw})};
}

double signed_area(const Polygon& polygon) {
  double area = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    area += cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  }
  return area / 2.0;
}

bool contains(const Polygon& polygon, Vec2 point) {
  // Even-odd ray casting along +x.
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vec2 a = polygon[i];
    const Vec2 b = polygon[j];
    if ((a.y > point.y) != (b.y > point.y)) {
      const double x_cross = a.x + (point.y - a.y) * (b.x - a.x) / (b.y - a.y);
      if (point.x < x_cross) inside = !inside;
    }
  }
  return inside;
}

namespace {
int orientation(Vec2 a, Vec2 b, Vec2 c) {
  const double v = cross(b - a, c - a);
  constexpr double eps = 1e-12;
  return v > eps ? 1 : (v < -eps ? -1 : 0);
}
bool on_segment(Vec2 a, Vec2 b, Vec2 p) {
  return std::min(a.x, b.x) - 1e-12 <= p.x && p.x <= std::max(a.x, b.x) + 1e-12 && std::min(a.y, b.y) - 1e-12 <= p.y &&
         p.y <= std::max(a.y, b.y) + 1e-12;
}
}  // namespace

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = orientation(a, b, c);
  const int o2 = orientation(a, b, d);
  const int o3 = orientation(c, d, a);
  const int o4 = orientation(c, d, b);
  if (o1 != o2 && o3 != o4) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}

bool segment_intersects_polygon(Vec2 a, Vec2 b, const Polygon& polygon) {
  if (polygon.empty()) return false;
  if (contains(polygon, a) || contains(polygon, b)) return true;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    if (segments_intersect(a, b, polygon[i], polygon[(i + 1) % polygon.size()])) return true;
  }
  return false;
}

namespace {
// True when some edge normal of `p` separates the two polygons.
bool has_separating_axis(const Polygon& p, const Polygon& q) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 edge = p[(i + 1) % p.size()] - p[i];
    const Vec2 axis{-edge.y, edge.x};
    double p_min = std::numeric_limits<double>::max(), p_max = -p_min;
    double q_min = p_min, q_max = -p_min;
    for (const Vec2& v : p) {
      p_min = std::min(p_min, dot(v, axis));
      p_max = std::max(p_max, dot(v, axis));
    }
    for (const Vec2& v : q) {
      q_min = std::min(q_min, dot(v, axis));
      q_max = std::max(q_max, dot(v, axis));
    }
    if (p_max < q_min || q_max < p_min) return true;
  }
  return false;
}
}  // namespace

bool same_polygon(const Polygon& a, const Polygon& b, double tolerance) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (distance(a[i], b[i]) > tolerance) return false;
  }
  return true;
}

Vec2 vertex_centroid(const Polygon& polygon) {
  if (polygon.empty()) return {0.0, 0.0};
  Vec2 sum{0.0, 0.0};
  for (const Vec2& v : polygon) sum = sum + v;
  const double n = static_cast<double>(polygon.size());
  return {sum.x / n, sum.y / n};
}

bool convex_polygons_overlap(const Polygon& a, const Polygon& b) {
  if (a.empty() || b.empty()) return false;
  return !has_separating_axis(a, b) && !has_separating_axis(b, a);
}

bool polygons_overlap(const Polygon& a, const Polygon& b) {
  if (a.empty() || b.empty()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (segment_intersects_polygon(a[i], a[(i + 1) % a.size()], b)) return true;
  }
  return contains(a, b.front());
}

double point_segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double len2 = dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return distance(p, a + t * ab);
}

double segment_polygon_distance(Vec2 a, Vec2 b, const Polygon& polygon) {
  if (polygon.empty()) return std::numeric_limits<double>::infinity();
  if (segment_intersects_polygon(a, b, polygon)) return 0.0;
  // Apart: the closest pair is a polygon corner to the segment, or an end of the segment to an edge.
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2 p = polygon[i];
    const Vec2 q = polygon[(i + 1) % polygon.size()];
    best = std::min(
        {best, point_segment_distance(p, a, b), point_segment_distance(a, p, q), point_segment_distance(b, p, q)});
  }
  return best;
}

double convex_polygons_distance(const Polygon& a, const Polygon& b) {
  if (a.empty() || b.empty()) return std::numeric_limits<double>::infinity();
  if (convex_polygons_overlap(a, b)) return 0.0;
  // Disjoint convex polygons: the closest pair involves a vertex of one and an edge of the other.
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [p, q] : {std::pair{&a, &b}, std::pair{&b, &a}}) {
    for (const Vec2& v : *p) {
      for (std::size_t i = 0; i < q->size(); ++i) {
        best = std::min(best, point_segment_distance(v, (*q)[i], (*q)[(i + 1) % q->size()]));
      }
    }
  }
  return best;
}

Bounds bounding_box(const Polygon& polygon) {
  Bounds box{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
             std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
  for (const Vec2& v : polygon) {
    box.min_x = std::min(box.min_x, v.x);
    box.min_y = std::min(box.min_y, v.y);
    box.max_x = std::max(box.max_x, v.x);
    box.max_y = std::max(box.max_y, v.y);
  }
  return box;
}

BoundingCircle bounding_circle(const Polygon& polygon) {
  BoundingCircle circle{vertex_centroid(polygon), 0.0};
  double squared = 0.0;
  for (const Vec2& v : polygon) {
    const double dx = v.x - circle.centre.x;
    const double dy = v.y - circle.centre.y;
    squared = std::max(squared, dx * dx + dy * dy);
  }
  circle.radius = std::sqrt(squared);
  return circle;
}

}  // namespace fleet::geometry
