// Plan-view geometry against analytic cases [Forklift thesis, section 5.1, eq. 5.1-5.4].

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>

#include "map/opendrive.hpp"

using namespace fleet::map;

namespace {

constexpr double kPi = std::numbers::pi;

Geometry make(GeometryKind kind, double length, double x = 0.0, double y = 0.0, double hdg = 0.0) {
  Geometry g;
  g.kind = kind;
  g.length = length;
  g.x = x;
  g.y = y;
  g.hdg = hdg;
  return g;
}

/// Clothoid end point by composite Simpson on the heading, independent of the Fresnel code.
RefPoint simpson_spiral(double x0, double y0, double h0, double k0, double k1, double length, double ds) {
  const double rate = (k1 - k0) / length;
  const int n = 200000;
  const double h = ds / n;
  double sx = 0.0, sy = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double u = i * h;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const double hd = h0 + k0 * u + 0.5 * rate * u * u;
    sx += w * std::cos(hd);
    sy += w * std::sin(hd);
  }
  return {x0 + sx * h / 3.0, y0 + sy * h / 3.0, h0 + k0 * ds + 0.5 * rate * ds * ds};
}

}  // namespace

TEST(OpenDriveGeometry, LineRunsAlongItsHeading) {
  const Geometry g = make(GeometryKind::kLine, 10.0, 1.0, 2.0, kPi / 4);
  const RefPoint p = evaluate_geometry(g, std::sqrt(2.0));
  EXPECT_NEAR(p.x, 2.0, 1e-12);
  EXPECT_NEAR(p.y, 3.0, 1e-12);
  EXPECT_NEAR(p.hdg, kPi / 4, 1e-12);
  // Beyond the length the point is clamped to the end rather than extrapolated.
  const RefPoint end = evaluate_geometry(g, 50.0);
  EXPECT_NEAR(end.x, 1.0 + 10.0 / std::sqrt(2.0), 1e-12);
}

TEST(OpenDriveGeometry, ArcOfKnownRadiusTurnsAQuarterCircle) {
  Geometry left = make(GeometryKind::kArc, 10.0);
  left.curvature = 0.5;                             // radius 2 m
  const RefPoint p = evaluate_geometry(left, kPi);  // a quarter of the circumference
  EXPECT_NEAR(p.x, 2.0, 1e-12);
  EXPECT_NEAR(p.y, 2.0, 1e-12);
  EXPECT_NEAR(p.hdg, kPi / 2, 1e-12);
  Geometry right = left;
  right.curvature = -0.5;
  const RefPoint q = evaluate_geometry(right, kPi);
  EXPECT_NEAR(q.x, 2.0, 1e-12);
  EXPECT_NEAR(q.y, -2.0, 1e-12);
  EXPECT_NEAR(q.hdg, -kPi / 2, 1e-12);
  // Every point of the arc stays on the circle about (0, 2).
  for (double s = 0.0; s <= 10.0; s += 0.37) {
    const RefPoint r = evaluate_geometry(left, s);
    EXPECT_NEAR(std::hypot(r.x, r.y - 2.0), 2.0, 1e-12);
  }
}

TEST(OpenDriveGeometry, FresnelIntegralsMatchTables) {
  struct Row {
    double x, c, s;
  };
  // Reference values of C(x) and S(x) (Abramowitz & Stegun, table 7.7; scipy.special.fresnel).
  const Row rows[] = {{0.5, 0.4923442258714464, 0.0647324328599963},
                      {1.0, 0.7798934003768228, 0.4382591473903548},
                      {2.0, 0.4882534060753408, 0.3434156783636982},
                      {-1.0, -0.7798934003768228, -0.4382591473903548}};
  for (const Row& r : rows) {
    double c = 0.0, s = 0.0;
    fresnel(r.x, c, s);
    EXPECT_NEAR(c, r.c, 1e-13) << "C(" << r.x << ")";
    EXPECT_NEAR(s, r.s, 1e-13) << "S(" << r.x << ")";
  }
  // Both branches (series below 1.5, continued fraction above) agree where they meet.
  double c1 = 0.0, s1 = 0.0, c2 = 0.0, s2 = 0.0;
  fresnel(1.5 - 1e-9, c1, s1);
  fresnel(1.5 + 1e-9, c2, s2);
  EXPECT_NEAR(c1, c2, 2.5e-9);  // |dC/dx|, |dS/dx| <= 1 over the 2e-9 gap
  EXPECT_NEAR(s1, s2, 2.5e-9);
}

TEST(OpenDriveGeometry, ClothoidFromZeroCurvatureEqualsScaledFresnel) {
  // Curvature from 0 growing at rate pi / a^2 gives (x, y) = a (C(s / a), S(s / a)).
  for (const double tau : {1.0, 2.0}) {
    const double length = 500.0;
    const double a = length / tau;
    Geometry g = make(GeometryKind::kSpiral, length);
    g.curv_start = 0.0;
    g.curv_end = kPi / (a * a) * length;
    double c = 0.0, s = 0.0;
    fresnel(tau, c, s);
    const RefPoint p = evaluate_geometry(g, length);
    EXPECT_NEAR(p.x, a * c, 1e-6) << "tau " << tau;
    EXPECT_NEAR(p.y, a * s, 1e-6) << "tau " << tau;
    EXPECT_NEAR(p.hdg, 0.5 * kPi * tau * tau, 1e-12);
  }
}

TEST(OpenDriveGeometry, ClothoidWithinOneMicrometreOver500Metres) {
  struct Case {
    double k0, k1;
  };
  // Growing, shrinking, sign-changing and nearly constant curvature; the last one takes the
  // quadrature path because its Fresnel arguments would be enormous.
  const Case cases[] = {{0.0, 0.008}, {0.008, 0.0}, {-0.01, 0.004}, {0.02, -0.005}, {0.01, 0.0100001}};
  for (const Case& c : cases) {
    Geometry g = make(GeometryKind::kSpiral, 500.0, 10.0, -5.0, 0.3);
    g.curv_start = c.k0;
    g.curv_end = c.k1;
    for (const double ds : {125.0, 250.0, 500.0}) {
      const RefPoint want = simpson_spiral(10.0, -5.0, 0.3, c.k0, c.k1, 500.0, ds);
      const RefPoint got = evaluate_geometry(g, ds);
      EXPECT_NEAR(got.x, want.x, 1e-6) << c.k0 << " -> " << c.k1 << " at " << ds;
      EXPECT_NEAR(got.y, want.y, 1e-6) << c.k0 << " -> " << c.k1 << " at " << ds;
      EXPECT_NEAR(got.hdg, want.hdg, 1e-12);
    }
  }
}

TEST(OpenDriveGeometry, ParamPoly3NormalizedRangeIsPlacedAndTurned) {
  // u = 10 p, v = 2 p^2 over p in [0, 1], placed at (1, 1) turned by 90 degrees; its declared
  // length 10 ends it at p = 1: u = 10, v = 2.
  Geometry g = make(GeometryKind::kParamPoly3, 10.0, 1.0, 1.0, kPi / 2);
  g.bu = 10.0;
  g.cv = 2.0;
  g.normalized = true;
  const RefPoint start = evaluate_geometry(g, 0.0);
  EXPECT_NEAR(start.x, 1.0, 1e-12);
  EXPECT_NEAR(start.y, 1.0, 1e-12);
  EXPECT_NEAR(start.hdg, kPi / 2, 1e-12);
  const RefPoint end = evaluate_geometry(g, 10.0);
  EXPECT_NEAR(end.x, 1.0 - 2.0, 1e-9);
  EXPECT_NEAR(end.y, 1.0 + 10.0, 1e-9);
  EXPECT_NEAR(end.hdg, kPi / 2 + std::atan2(4.0, 10.0), 1e-9);  // du/dp = 10, dv/dp = 4 p
  // Half-way along the arc lies beyond p = 0.5 (u = 5): the speed |(10, 4 p)| grows with p, so
  // the first half of p covers less than half the arc.
  EXPECT_GT(evaluate_geometry(g, 5.0).y, 1.0 + 5.0 + 1e-3);
}

/// Arc length of the cubic (u(p), v(p)) from 0 to `p`, by composite Simpson with many steps:
/// independent of the evaluator's Gauss-Legendre and Newton steps.
double simpson_arc_length(const Geometry& g, double p, int steps = 20000) {
  const auto speed = [&](double q) {
    return std::hypot(g.bu + q * (2.0 * g.cu + 3.0 * g.du * q), g.bv + q * (2.0 * g.cv + 3.0 * g.dv * q));
  };
  const double h = p / steps;
  double sum = speed(0.0) + speed(p);
  for (int i = 1; i < steps; ++i) sum += (i % 2 ? 4.0 : 2.0) * speed(i * h);
  return sum * h / 3.0;
}

/// Where the cubic is after arc length `s` (scaled so that `g.length` is the whole curve), found
/// by bisection on the Simpson arc length.
std::pair<double, double> independent_point(const Geometry& g, double s) {
  const double p_end = g.normalized ? 1.0 : g.length;
  const double target = s * simpson_arc_length(g, p_end) / g.length;
  double lo = 0.0, hi = p_end;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (simpson_arc_length(g, mid, 2000) < target ? lo : hi) = mid;
  }
  const double p = 0.5 * (lo + hi);
  const double u = g.au + p * (g.bu + p * (g.cu + p * g.du));
  const double v = g.av + p * (g.bv + p * (g.cv + p * g.dv));
  // The frame of make(): origin (1, 1), heading 0.
  return {g.x + u, g.y + v};
}

// Regression: paramPoly3 was evaluated at p = s - s0 (or its normalized share), which puts points
// on the right curve but shifted along it wherever the cubic's speed is not 1.
TEST(OpenDriveGeometry, ParamPoly3FollowsArcLengthInBothRanges) {
  // u = p + 0.03 p^2 / 40, v = 0.001 p^2 - 1e-5 p^3 over p in [0, 40]: the speed runs from 1 to about
  // 1.06, as on real ramps.
  Geometry g = make(GeometryKind::kParamPoly3, 40.0, 1.0, 1.0, 0.0);
  g.normalized = false;
  g.bu = 1.0;
  g.cu = 0.03 / 40.0;
  g.cv = 0.04 / 40.0;
  g.dv = -0.0004 / 40.0;
  g.length = simpson_arc_length(g, 40.0);  // the file's length is the curve's length
  // With that length the p range is [0, length]; the coefficients are for p up to 40, so scale
  // them to keep the curve: p' = p * 40 / length.
  const double k = 40.0 / g.length;
  g.bu *= k;
  g.cu *= k * k;
  g.cv *= k * k;
  g.dv *= k * k * k;
  for (const double s : {0.0, 3.0, 10.0, 20.0, 33.3, g.length}) {
    const auto [x, y] = independent_point(g, s);
    const RefPoint got = evaluate_geometry(g, s);
    EXPECT_NEAR(got.x, x, 1e-4) << "arcLength range, s = " << s;
    EXPECT_NEAR(got.y, y, 1e-4) << "arcLength range, s = " << s;
  }
  // The same curve over p in [0, 1].
  Geometry n = g;
  n.normalized = true;
  n.bu = g.bu * g.length;
  n.cu = g.cu * g.length * g.length;
  n.cv = g.cv * g.length * g.length;
  n.dv = g.dv * g.length * g.length * g.length;
  for (const double s : {0.0, 7.5, 20.0, g.length}) {
    const auto [x, y] = independent_point(n, s);
    const RefPoint got = evaluate_geometry(n, s);
    EXPECT_NEAR(got.x, x, 1e-4) << "normalized range, s = " << s;
    EXPECT_NEAR(got.y, y, 1e-4) << "normalized range, s = " << s;
  }
  // The curve is the same in both modes.
  EXPECT_NEAR(evaluate_geometry(n, 12.0).x, evaluate_geometry(g, 12.0).x, 1e-9);
}

TEST(OpenDriveGeometry, ParamPoly3EndsWhereTheFilePutsItsEnd) {
  // A declared length slightly off the curve's own (rounding in a file): s = length is still
  // the end of the p range.
  Geometry g = make(GeometryKind::kParamPoly3, 10.0, 1.0, 1.0, 0.0);
  g.bu = 1.0;
  g.cv = 0.02;
  g.normalized = false;
  const RefPoint end = evaluate_geometry(g, 10.0);
  EXPECT_NEAR(end.x, 11.0, 1e-9);
  EXPECT_NEAR(end.y, 3.0, 1e-9);
  EXPECT_NEAR(end.hdg, std::atan(0.4), 1e-9);
  // Half-way along the arc is not p = 5: the speed grows along the curve.
  const auto [x, y] = independent_point(g, 5.0);
  EXPECT_NEAR(evaluate_geometry(g, 5.0).x, x, 1e-4);
  EXPECT_GT(std::abs(evaluate_geometry(g, 5.0).x - 6.0), 1e-3);
  // The same numbers read as normalized would put the point elsewhere: the mode matters.
  g.normalized = true;
  EXPECT_GT(std::abs(evaluate_geometry(g, 5.0).x - 6.0), 1.0);
}

TEST(OpenDriveGeometry, Poly3FollowsArcLength) {
  // v = 0.5 u^2: arc length to u = 1 is (sqrt(2) + asinh(1)) / 2.
  Geometry g = make(GeometryKind::kPoly3, 3.0);
  g.c = 0.5;
  const double s1 = 0.5 * (std::sqrt(2.0) + std::asinh(1.0));
  const RefPoint p = evaluate_geometry(g, s1);
  EXPECT_NEAR(p.x, 1.0, 1e-9);
  EXPECT_NEAR(p.y, 0.5, 1e-9);
  EXPECT_NEAR(p.hdg, kPi / 4, 1e-9);
}

TEST(OpenDriveGeometry, LaneCentresAddInnerWidthsAndOffset) {
  Road road;
  road.length = 20.0;
  Geometry g = make(GeometryKind::kLine, 20.0);
  road.plan_view.push_back(g);
  road.lane_offsets.push_back({0.0, 0.5, 0.0, 0.0, 0.0});
  LaneSection sec;
  sec.left.push_back({1, "driving", {{0.0, 3.0, 0.0, 0.0, 0.0}}, {}, {}, 0});
  sec.right.push_back({-1, "driving", {{0.0, 3.0, 0.0, 0.0, 0.0}}, {}, {}, 0});
  sec.right.push_back({-2, "shoulder", {{0.0, 2.0, 0.1, 0.0, 0.0}, {10.0, 1.0, 0.0, 0.0, 0.0}}, {}, {}, 0});
  road.sections.push_back(sec);
  EXPECT_NEAR(lane_center_t(road, 0, 1, 4.0), 0.5 + 1.5, 1e-12);
  EXPECT_NEAR(lane_center_t(road, 0, -1, 4.0), 0.5 - 1.5, 1e-12);
  EXPECT_NEAR(lane_center_t(road, 0, -2, 4.0), 0.5 - 3.0 - 0.5 * (2.0 + 0.4), 1e-12);
  // From sOffset 10 on the second width record applies, measured from its own start.
  EXPECT_NEAR(lane_width_at(road, 0, -2, 12.0), 1.0, 1e-12);
  const RefPoint c = lane_center(road, 0, 1, 4.0);
  EXPECT_NEAR(c.x, 4.0, 1e-12);
  EXPECT_NEAR(c.y, 2.0, 1e-12);
}
