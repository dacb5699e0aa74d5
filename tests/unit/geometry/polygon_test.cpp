#include "geometry/polygon.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace fleet::geometry;

TEST(Angles, NormalizeWrapsIntoHalfOpenRange) {
  EXPECT_NEAR(normalize_angle(3 * std::numbers::pi), -std::numbers::pi, 1e-12);
  EXPECT_NEAR(normalize_angle(-0.5), -0.5, 1e-12);
  EXPECT_NEAR(angle_diff(0.1, 2 * std::numbers::pi - 0.1), 0.2, 1e-12);
}

TEST(Frames, BodyToMapAndBackRoundTrips) {
  const Pose2 pose{1.0, 2.0, 0.7};
  const Vec2 body{0.05, -0.02};
  const Vec2 back = map_to_body(pose, body_to_map(pose, body));
  EXPECT_NEAR(back.x, body.x, 1e-12);
  EXPECT_NEAR(back.y, body.y, 1e-12);
}

TEST(Footprint, CornersAreCounterClockwiseWithTheRightArea) {
  const Polygon p = footprint_polygon({0, 0, 0.3}, {0.25, 0.16});
  EXPECT_NEAR(signed_area(p), 0.25 * 0.16, 1e-12);
  EXPECT_NEAR(signed_area(footprint_polygon({0, 0, 0}, {0.25, 0.16}, 0.01)), 0.27 * 0.18, 1e-12);
}

TEST(Polygon, ContainsAndSegmentCrossing) {
  const Polygon square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_TRUE(contains(square, {0.5, 0.5}));
  EXPECT_FALSE(contains(square, {1.5, 0.5}));
  EXPECT_TRUE(segment_intersects_polygon({-1, 0.5}, {2, 0.5}, square));
  EXPECT_FALSE(segment_intersects_polygon({-1, 1.5}, {2, 1.5}, square));
  EXPECT_TRUE(segment_intersects_polygon({0.2, 0.2}, {0.3, 0.3}, square));
}

TEST(Polygon, ConvexOverlapBySeparatingAxes) {
  const Polygon a = footprint_polygon({0, 0, 0}, {0.25, 0.16});
  EXPECT_TRUE(convex_polygons_overlap(a, footprint_polygon({0.2, 0.0, 0.0}, {0.25, 0.16})));
  EXPECT_FALSE(convex_polygons_overlap(a, footprint_polygon({0.3, 0.0, 0.0}, {0.25, 0.16})));
  // Rotated by 45 degrees: the axis-aligned boxes overlap, the real shapes do not.
  EXPECT_FALSE(convex_polygons_overlap(footprint_polygon({0, 0, 0.785}, {0.4, 0.02}),
                                       footprint_polygon({0.15, -0.15, 0.785}, {0.4, 0.02})));
}

TEST(Polygon, AnyPolygonsOverlapByCrossingEdgesOrContainment) {
  // An L whose notch is the square [1,2] x [1,2].
  const Polygon ell{{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
  EXPECT_FALSE(polygons_overlap(ell, footprint_polygon({1.5, 1.5, 0}, {0.5, 0.5})));  // in the notch
  EXPECT_TRUE(polygons_overlap(ell, footprint_polygon({1.5, 0.9, 0}, {0.5, 0.5})));   // across an edge
  EXPECT_TRUE(polygons_overlap(ell, footprint_polygon({0.5, 0.5, 0}, {0.2, 0.2})));   // inside it
  EXPECT_TRUE(polygons_overlap(footprint_polygon({0.5, 0.5, 0}, {0.2, 0.2}), ell));   // it inside
  EXPECT_FALSE(polygons_overlap(ell, {}));
}

TEST(Polygon, ConvexDistanceIsTheGapOrZero) {
  const Polygon a = footprint_polygon({0, 0, 0}, {0.25, 0.16});
  EXPECT_NEAR(convex_polygons_distance(a, footprint_polygon({0.35, 0.0, 0.0}, {0.25, 0.16})), 0.10, 1e-12);
  EXPECT_NEAR(convex_polygons_distance(a, footprint_polygon({0.0, 0.26, 0.0}, {0.25, 0.16})), 0.10, 1e-12);
  EXPECT_DOUBLE_EQ(convex_polygons_distance(a, footprint_polygon({0.2, 0.0, 0.0}, {0.25, 0.16})), 0.0);
  EXPECT_NEAR(point_segment_distance({0.5, 1.0}, {0, 0}, {1, 0}), 1.0, 1e-12);
  EXPECT_NEAR(point_segment_distance({2.0, 0.0}, {0, 0}, {1, 0}), 1.0, 1e-12);
}

TEST(Polygon, SegmentDistanceIsTheGapOrZero) {
  const Polygon box{{1, 1}, {2, 1}, {2, 2}, {1, 2}};
  EXPECT_DOUBLE_EQ(segment_polygon_distance({0, 0}, {3, 3}, box), 0.0);          // through it
  EXPECT_DOUBLE_EQ(segment_polygon_distance({1.5, 1.5}, {1.6, 1.6}, box), 0.0);  // inside it
  EXPECT_NEAR(segment_polygon_distance({0, 0.5}, {3, 0.5}, box), 0.5, 1e-12);    // passes below
  EXPECT_NEAR(segment_polygon_distance({0, 3}, {0.7, 1.5}, box), 0.3, 1e-12);    // ends short: its end to an edge
  EXPECT_NEAR(segment_polygon_distance({0, 0.8}, {0.8, 0}, box), 1.2 / std::sqrt(2.0),
              1e-12);  // corner (1, 1) to x + y = 0.8
}
