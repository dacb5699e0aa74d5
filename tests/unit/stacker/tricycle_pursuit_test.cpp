// Pure pursuit of the stacker's rear axle along a route: it stops where it is told to, its centre
// on the route's end when it stops short by the centre's lead.
#include "control/tricycle_pursuit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "sim/tricycle.hpp"

namespace fleet::control {
namespace {

// Drives the body along `path` until the pursuit says it arrived; returns the rear axle's pose.
geometry::Pose2 drive_to_end(const std::vector<geometry::Vec2>& path, const TricyclePursuitParams& params) {
  sim::TricycleParams body;
  sim::Tricycle t(body, {0.0, 0.0, 0.0});
  constexpr double kDt = 0.02;
  for (int i = 0; i < 5000; ++i) {
    const TricyclePursuitOutput out = pursue(t.pose(), path, std::numeric_limits<double>::infinity(),
                                             t.state().theta_steer, params, body.geometry.wheelbase);
    if (out.arrived) break;
    t.step(out.command, kDt);
  }
  // Let it come to rest.
  for (int i = 0; i < 200; ++i) t.step({0.0, t.state().theta_steer}, kDt);
  return t.pose();
}

TEST(TricyclePursuit, StopsAtTheEndOrShortOfItByTheCentresLead) {
  const std::vector<geometry::Vec2> path{{0.0, 0.0}, {3.0, 0.0}, {6.0, 0.0}};
  TricyclePursuitParams params;
  const geometry::Pose2 at_end = drive_to_end(path, params);
  EXPECT_NEAR(at_end.x, 6.0, 0.2);
  params.stop_short = 0.75;
  const geometry::Pose2 short_of_end = drive_to_end(path, params);
  EXPECT_NEAR(short_of_end.x, 6.0 - 0.75, 0.2);
  EXPECT_NEAR(short_of_end.y, 0.0, 0.02);
}

// A route leading off behind the stacker makes it pivot about its rear axle, its front sweeping
// round: only once it has room to go, never while traffic holds it.
TEST(TricyclePursuit, PivotsTowardsARouteBehindOnlyWithRoomToGo) {
  const std::vector<geometry::Vec2> behind{{0.0, 0.0}, {-3.0, 0.0}};
  const TricyclePursuitParams params;
  const sim::TricycleParams body;
  const geometry::Pose2 rear{0.0, 0.0, 0.0};
  for (const double held : {0.0, -1.0}) {
    const TricyclePursuitOutput out = pursue(rear, behind, held, 0.0, params, body.geometry.wheelbase);
    EXPECT_EQ(out.command.v_steer, 0.0) << "room " << held;
    EXPECT_EQ(out.command.theta_steer, 0.0) << "room " << held;
  }
  const TricyclePursuitOutput go = pursue(rear, behind, 1.0, 0.0, params, body.geometry.wheelbase);
  EXPECT_NEAR(std::abs(go.command.theta_steer), M_PI / 2.0, 1e-6);
}

}  // namespace
}  // namespace fleet::control
