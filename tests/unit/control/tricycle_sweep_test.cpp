// The stacker's drive rolled forward on its body model: what its look-ahead sweeps and what
// traffic reserves through the bends.
#include "control/tricycle_sweep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "vehicle/vehicle_types.hpp"

namespace fleet::control {
namespace {

TricycleDrive stacker() {
  return tricycle_drive_for(vehicle::find_robot_type("stacker")->defaults);
}

std::vector<geometry::Vec2> straight(double length) {
  std::vector<geometry::Vec2> path;
  for (double x = 0.0; x <= length + 1e-9; x += 0.5) path.push_back({x, 0.0});
  return path;
}

TEST(TricycleSweep, TheDriveTakesTheProfilesBodyAndSpeed) {
  const vehicle::VehicleProfile& profile = vehicle::find_robot_type("stacker")->defaults;
  const TricycleDrive drive = stacker();
  EXPECT_DOUBLE_EQ(drive.pursuit.max_speed, profile.max_speed);
  EXPECT_DOUBLE_EQ(drive.body.geometry.wheelbase, profile.wheelbase);
  // The rear axle 0.75 m behind the footprint's centre: the centre offset says as much.
  EXPECT_NEAR(drive.centre_offset(), -profile.rear_axle_x, 1e-9);
}

TEST(TricycleSweep, FromRestItAcceleratesAndAtSpeedItStartsAtTopSpeed) {
  const TricycleDrive drive = stacker();
  const auto path = straight(6.0);
  const auto from_rest = drive_along(drive, path, false);
  const auto at_speed = drive_along(drive, path, true);
  ASSERT_GT(from_rest.size(), 2u);
  ASSERT_GT(at_speed.size(), 2u);
  const double first_rest = geometry::distance(from_rest[0].position(), from_rest[1].position());
  const double first_speed = geometry::distance(at_speed[0].position(), at_speed[1].position());
  EXPECT_LT(first_rest, 0.2 * drive.pursuit.max_speed * drive.control_period);
  EXPECT_NEAR(first_speed, drive.pursuit.max_speed * drive.control_period, 0.01);
  // The footprint's centre, ahead of the rear axle that starts on the path's first point.
  EXPECT_NEAR(from_rest.front().x, drive.centre_offset(), 0.02);
  // Along a straight path it stays on it, heading along it, and ends near its end.
  for (const auto& p : from_rest) {
    EXPECT_NEAR(p.y, 0.0, 1e-6);
    EXPECT_NEAR(p.yaw, 0.0, 1e-6);
  }
  EXPECT_NEAR(from_rest.back().x - drive.centre_offset(), 6.0, drive.pursuit.arrive_tolerance + 0.05);
}

TEST(TricycleSweep, RollingForwardStopsAfterTheDistanceAskedFor) {
  const TricycleDrive drive = stacker();
  sim::Tricycle ghost(drive.body, {0.0, 0.0, 0.0});
  const auto poses = roll_forward(ghost, straight(10.0), drive.pursuit, drive.body.geometry.wheelbase, 0.05, 2.0);
  ASSERT_FALSE(poses.empty());
  EXPECT_GE(poses.back().x, 2.0);
  EXPECT_LT(poses.back().x, 2.0 + drive.pursuit.max_speed * 0.05 + 1e-9);
}

TEST(TricycleSweep, PastATightBendTheCentreSwingsOutBeyondTheLane) {
  // East along y = 0, then a left turn of radius 1 m about (4, 1) into x = 5 northwards.
  std::vector<geometry::Vec2> path = straight(4.0);
  for (int k = 1; k <= 6; ++k) {
    const double theta = -std::numbers::pi / 2 + std::numbers::pi / 2 * k / 6;
    path.push_back({4.0 + std::cos(theta), 1.0 + std::sin(theta)});
  }
  for (double y = 1.5; y <= 6.0; y += 0.5) path.push_back({5.0, y});
  const TricycleDrive drive = stacker();
  double outside = 0.0;
  for (const auto& centre : drive_along(drive, path, true)) {
    if (centre.y > 1.0) outside = std::max(outside, centre.x - 5.0);  // past the bend, beyond the lane
  }
  EXPECT_GT(outside, 0.05) << "the centre stays on the lane past the bend";
}

}  // namespace
}  // namespace fleet::control
