#include "control/attractor_dynamics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "geometry/polygon.hpp"
#include "sim/tricycle.hpp"

using namespace fleet::control;
using fleet::geometry::Polygon;
using fleet::geometry::Pose2;
using fleet::geometry::Vec2;

namespace {

constexpr double kPi = std::numbers::pi;

Polygon box(double x0, double y0, double x1, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

/// What the two S300s return, simplified: points along the obstacles' edges every 3 cm within 8 m, in the
/// vehicle frame (no occlusion).
std::vector<Vec2> scan(const Pose2& pose, const std::vector<Polygon>& obstacles) {
  std::vector<Vec2> points;
  for (const Polygon& poly : obstacles) {
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const Vec2 a = poly[i];
      const Vec2 b = poly[(i + 1) % poly.size()];
      const int n = std::max(1, static_cast<int>(fleet::geometry::distance(a, b) / 0.03));
      for (int k = 0; k < n; ++k) {
        const Vec2 p = fleet::geometry::map_to_body(pose, a + (static_cast<double>(k) / n) * (b - a));
        if (fleet::geometry::norm(p) < 8.0) points.push_back(p);
      }
    }
  }
  return points;
}

struct RunResult {
  bool reached = false;
  bool collided = false;
  double gap_crossing_y = std::numeric_limits<double>::quiet_NaN();  ///< y where the rear axle crossed x = 5
  Pose2 pose;
};

/// Drives the simulated stacker with the navigator towards `target` among `obstacles`.
RunResult drive(const Pose2& start, Vec2 target, const std::vector<Polygon>& obstacles, double seconds,
                const AttractorParams& params = {}) {
  fleet::sim::TricycleParams vp;
  fleet::sim::Tricycle body(vp, start);
  AttractorNavigator nav(params, vp.geometry, 3);
  nav.reset_speed(params.desired_speed);
  RunResult r;
  const double dt = 0.05;
  for (double t = 0.0; t < seconds; t += dt) {
    const std::vector<Vec2> points = scan(body.pose(), obstacles);
    const AttractorOutput out = nav.update(body.pose(), {target, 1, -1.0}, points, dt);
    if (out.target_distance < 0.3) {
      r.reached = true;
      break;
    }
    const double x_before = body.pose().x;
    body.step(out.command, dt);
    if (x_before < 5.0 && body.pose().x >= 5.0) r.gap_crossing_y = body.pose().y;
    for (const Polygon& o : obstacles) {
      if (fleet::geometry::polygons_overlap(body.footprint_in_map(), o)) r.collided = true;
    }
  }
  r.pose = body.pose();
  return r;
}

}  // namespace

TEST(AttractorDynamics, DefaultGainsRespectTheSeedsOrdering) {
  const AttractorParams p;  // [eq. 3.18]
  EXPECT_LE(p.lambda_tar * 4.0, p.c_v_tar);
  EXPECT_LE(p.beta1 * 2.0, p.c_v_obs);
  EXPECT_LE(p.lambda_tar * 4.0, p.beta1);
}

TEST(AttractorDynamics, TargetForceAttractsAndThresholdSpansHalf) {
  EXPECT_GT(target_force(0.0, 0.5, 1.0), 0.0);  // target to the left: turn left
  EXPECT_LT(target_force(0.0, -0.5, 1.0), 0.0);
  EXPECT_NEAR(target_force(0.3, 0.3, 1.0), 0.0, 1e-12);
  EXPECT_NEAR(speed_threshold(1e9, 20.0), 0.5, 1e-6);  // [eq. 3.15] atan(cU)/pi
  EXPECT_NEAR(speed_threshold(-1e9, 20.0), -0.5, 1e-6);
  EXPECT_EQ(speed_threshold(0.0, 20.0), 0.0);
}

TEST(AttractorDynamics, SectorsLookWhereTheStackerGoes) {
  const AttractorParams p;
  const fleet::sim::TricycleGeometry g;
  const std::vector<Vec2> ahead{{3.0, 0.0}};
  const std::vector<Sector> fwd = frontal_sectors(ahead, 0.0, g, p);
  ASSERT_EQ(fwd.size(), 21u);
  EXPECT_NEAR(fwd[10].clearance, 3.0 - g.front_x(), 1e-12);
  EXPECT_NEAR(fwd[1].bearing - fwd[0].bearing, 2.0 * kPi / 41.0, 1e-12);  // 8.78 deg
  EXPECT_NEAR(fwd[20].bearing, 10.0 * 2.0 * kPi / 41.0, 1e-12);
  // Driving backwards the same point is behind, outside the 21 used sectors.
  for (const Sector& s : frontal_sectors(ahead, kPi, g, p)) EXPECT_FALSE(std::isfinite(s.clearance));
  // A point beside the chassis counts from the chassis side.
  const std::vector<Vec2> beside{{0.0, 1.0}};
  const std::vector<Sector> side = frontal_sectors(beside, 0.0, g, p);
  double best = std::numeric_limits<double>::infinity();
  for (const Sector& s : side) best = std::min(best, s.clearance);
  EXPECT_NEAR(best, 1.0 - g.width / 2.0, 1e-9);
}

TEST(AttractorDynamics, WithoutObstaclesTheHeadingConvergesOnTheTarget) {
  for (double bearing : {kPi / 2.0, -2.5, 0.6}) {
    const Vec2 target{20.0 * std::cos(bearing), 20.0 * std::sin(bearing)};
    fleet::sim::Tricycle body(fleet::sim::TricycleParams{}, {});
    AttractorNavigator nav(AttractorParams{}, body.params().geometry);
    nav.reset_speed(0.5);
    AttractorOutput out;
    for (int i = 0; i < 400; ++i) {
      out = nav.update(body.pose(), {target, 1, -1.0}, {}, 0.05);
      body.step(out.command, 0.05);
    }
    EXPECT_NEAR(fleet::geometry::angle_diff(body.pose().yaw, out.psi_tar), 0.0, 0.02) << bearing;
    EXPECT_NEAR(out.speed, 0.5, 1e-6);
    EXPECT_EQ(out.f_obs, 0.0);
  }
}

TEST(AttractorDynamics, ReversingTurnsTheRearTowardsTheTarget) {
  fleet::sim::Tricycle body(fleet::sim::TricycleParams{}, {});
  AttractorNavigator nav(AttractorParams{}, body.params().geometry);
  nav.reset_speed(0.3);
  const Vec2 target{-6.0, 3.0};
  AttractorOutput out;
  for (int i = 0; i < 800; ++i) {
    out = nav.update(body.pose(), {target, -1, 0.3}, {}, 0.05);
    if (out.target_distance < 0.1) break;
    body.step(out.command, 0.05);
  }
  EXPECT_LT(out.target_distance, 0.1);
}

TEST(AttractorDynamics, ObstacleAheadTurnsAwayAndSlowsDown) {
  // A pallet 0.6 m ahead of the bumper, mostly left of the heading; the target lies straight on.
  const Pose2 pose{0.0, 0.0, 0.0};
  const std::vector<Polygon> obstacles{box(2.2, -0.15, 3.0, 0.9)};
  const std::vector<Vec2> points = scan(pose, obstacles);
  AttractorParams p;
  AttractorNavigator nav(p, fleet::sim::TricycleGeometry{});
  nav.reset_speed(p.desired_speed);
  AttractorOutput out;
  for (int i = 0; i < 60; ++i) out = nav.update(pose, {{10.0, 0.0}, 1, -1.0}, points, 0.05);
  EXPECT_LT(out.f_obs, -0.05);  // repelled to the right
  EXPECT_LT(out.heading_rate, 0.0);
  EXPECT_GT(out.alpha, 0.3);  // U > 0: obstacles dominate the speed [eq. 3.14-3.16]
  EXPECT_NEAR(out.min_clearance, 2.2 - 1.6, 1e-3);
  EXPECT_NEAR(out.v_obs, out.min_clearance / p.time_to_contact, 1e-9);  // [eq. 3.13]
  EXPECT_LT(out.speed, p.desired_speed - 0.1);
  EXPECT_NEAR(out.speed, out.v_obs, 0.06);
  // Mirrored obstacle, mirrored answer.
  const std::vector<Vec2> mirrored = scan(pose, {box(2.2, -0.9, 3.0, 0.15)});
  AttractorNavigator nav2(p, fleet::sim::TricycleGeometry{});
  EXPECT_NEAR(nav2.update(pose, {{10.0, 0.0}, 1, -1.0}, mirrored, 0.05).f_obs, -out.f_obs, 1e-9);
}

TEST(AttractorDynamics, NoiseIsSeededAndBreaksASymmetricStandOff) {
  AttractorParams p;
  p.noise_variance = 0.01;
  const Pose2 pose{};
  const std::vector<Vec2> points = scan(pose, {box(2.8, -0.4, 3.6, 0.4)});
  AttractorNavigator a(p, {}, 11);
  AttractorNavigator b(p, {}, 11);
  AttractorNavigator c(p, {}, 12);
  const AttractorOutput oa = a.update(pose, {{10.0, 0.0}, 1, -1.0}, points, 0.05);
  const AttractorOutput ob = b.update(pose, {{10.0, 0.0}, 1, -1.0}, points, 0.05);
  const AttractorOutput oc = c.update(pose, {{10.0, 0.0}, 1, -1.0}, points, 0.05);
  EXPECT_NEAR(oa.f_obs, 0.0, 1e-9);  // perfectly symmetric: a repeller right on the heading
  EXPECT_EQ(oa.f_stoch, ob.f_stoch);
  EXPECT_NE(oa.f_stoch, oc.f_stoch);
  EXPECT_NE(oa.heading_rate, 0.0);
}

TEST(AttractorDynamics, ReachesATargetThroughAGapBetweenTwoObstacles) {
  // Two 1 m x 1.5 m blocks 5 m ahead leave a 1.6 m gap whose right edge cuts into the straight line; the target
  // lies 10 m ahead.
  const std::vector<Polygon> obstacles{box(4.5, 1.5, 5.5, 3.0), box(4.5, -1.6, 5.5, -0.1)};
  const RunResult r = drive({0.0, 0.0, 0.0}, {10.0, 0.0}, obstacles, 60.0);
  EXPECT_TRUE(r.reached);
  EXPECT_FALSE(r.collided);
  EXPECT_GT(r.gap_crossing_y, -0.1 + 0.374);
  EXPECT_LT(r.gap_crossing_y, 1.5 - 0.374);
  // Without the obstacle dynamics the same run hits the right block: the test can fail.
  AttractorParams blind;
  blind.beta1 = 0.0;
  EXPECT_TRUE(drive({0.0, 0.0, 0.0}, {10.0, 0.0}, obstacles, 60.0, blind).collided);
}
