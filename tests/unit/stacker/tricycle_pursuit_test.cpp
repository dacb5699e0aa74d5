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

}  // namespace
}  // namespace fleet::control
