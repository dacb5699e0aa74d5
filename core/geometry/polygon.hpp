#pragma once

#include <vector>

#include "geometry/pose.hpp"

namespace fleet::geometry {

using Polygon = std::vector<Vec2>;

/// A rectangular robot footprint centred on the body frame origin.
struct Footprint {
  double length = 0.25;  ///< along body x, metres
  double width = 0.16;   ///< along body y, metres
};

/// The footprint's corners in the map frame, counter-clockwise, optionally grown by `margin` on
/// every side.
Polygon footprint_polygon(const Pose2& pose, const Footprint& footprint, double margin = 0.0);

/// Shoelace area; positive for counter-clockwise polygons.
double signed_area(const Polygon& polygon);

bool contains(const Polygon& polygon, Vec2 point);

/// True when the closed segments ab and cd share a point.
bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d);

/// True when the segment ab touches the polygon's boundary or lies inside it.
bool segment_intersects_polygon(Vec2 a, Vec2 b, const Polygon& polygon);

/// Overlap test for two convex polygons by the separating axis theorem.
bool convex_polygons_overlap(const Polygon& a, const Polygon& b);

/// Whether two polygons have as many vertices and each lies within `tolerance` metres of its
/// counterpart: a body reported again from about where it stood.
bool same_polygon(const Polygon& a, const Polygon& b, double tolerance);

/// The mean of the polygon's vertices ({0, 0} for an empty one).
Vec2 vertex_centroid(const Polygon& polygon);

/// A circle holding every vertex of a polygon: centred on the vertices' mean, through the farthest.
struct BoundingCircle {
  Vec2 centre;
  double radius = 0.0;
};
BoundingCircle bounding_circle(const Polygon& polygon);

/// Overlap test for any two simple polygons: an edge of one crosses an edge of the other, or one
/// lies inside the other.
bool polygons_overlap(const Polygon& a, const Polygon& b);

/// Distance from `p` to the closed segment ab.
double point_segment_distance(Vec2 p, Vec2 a, Vec2 b);

/// Gap between the closed segment ab and a simple polygon: 0 when it touches or enters it.
double segment_polygon_distance(Vec2 a, Vec2 b, const Polygon& polygon);

/// Gap between two convex polygons: 0 when they touch or overlap.
double convex_polygons_distance(const Polygon& a, const Polygon& b);

struct Bounds {
  double min_x = 0.0;
  double min_y = 0.0;
  double max_x = 0.0;
  double max_y = 0.0;

  bool contains(Vec2 p) const { return p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y; }
};

Bounds bounding_box(const Polygon& polygon);

}  // namespace fleet::geometry
