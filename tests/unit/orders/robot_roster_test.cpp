#include "orders/robot_roster.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <set>
#include <string>

#include "two_forklifts.hpp"

namespace fleet::orders {
namespace {

/// Forklifts fl1 and fl2, 1.0 m long and 0.6 m wide; fl1 has reported and stands at the origin
/// facing +x, fl2 is entered but has not reported.
struct Yard {
  config::FleetConfig config = test::two_forklifts();
  RobotRoster roster{config};

  Yard() {
    RobotEntry& fl1 = roster.entries()["fl1"];
    fl1.id = "fl1";
    fl1.fleet_id = "forklifts";
    fl1.registered = true;
    fl1.last.pose = {0.0, 0.0, 0.0};
    RobotEntry& fl2 = roster.entries()["fl2"];
    fl2.id = "fl2";
    fl2.last.pose = {10.0, 0.0, 0.0};
  }
};

geometry::Polygon square(double cx, double cy, double half) {
  return {{cx - half, cy - half}, {cx + half, cy - half}, {cx + half, cy + half}, {cx - half, cy + half}};
}

TEST(RobotRoster, OnlyRobotsThatReportedAreRegistered) {
  Yard yard;
  EXPECT_TRUE(yard.roster.registered("fl1"));
  EXPECT_FALSE(yard.roster.registered("fl2"));
  EXPECT_FALSE(yard.roster.registered("ghost"));
  EXPECT_EQ(yard.roster.registered_ids(), std::set<std::string>{"fl1"});
  EXPECT_EQ(yard.roster.registered_count(), 1);
  yard.roster.entries()["fl1"].lost = true;
  EXPECT_TRUE(yard.roster.registered("fl1")) << "a lost robot has still reported";
}

TEST(RobotRoster, ABodyIsTheFleetsFootprintWhereTheRobotLastStood) {
  Yard yard;
  RobotEntry& fl1 = yard.roster.entries()["fl1"];
  fl1.last.pose = {2.0, 1.0, std::numbers::pi / 2};
  const geometry::Polygon body = yard.roster.body_of(fl1);
  ASSERT_EQ(body.size(), 4u);
  const auto bounds = geometry::bounding_box(body);
  EXPECT_NEAR(bounds.max_x - bounds.min_x, 0.6, 1e-9) << "turned a quarter: its width lies along x";
  EXPECT_NEAR(bounds.max_y - bounds.min_y, 1.0, 1e-9);
  EXPECT_NEAR((bounds.max_x + bounds.min_x) / 2, 2.0, 1e-9);
  EXPECT_NEAR((bounds.max_y + bounds.min_y) / 2, 1.0, 1e-9);
}

TEST(RobotRoster, OnlyARegisteredBodyCoversAnArea) {
  Yard yard;
  EXPECT_EQ(yard.roster.robot_under(square(0.4, 0.0, 0.2)), "fl1");
  EXPECT_EQ(yard.roster.robot_under(square(2.0, 0.0, 0.2)), "");
  EXPECT_EQ(yard.roster.robot_under(square(10.0, 0.0, 0.2)), "") << "fl2 has not reported: its pose is no body";
}

TEST(RobotRoster, ABodyStandsOnAPlaceOrWhereAVehicleHandlesItsLoad) {
  Yard yard;
  map::LoadingArea area;
  area.id = "A1";
  area.pose = {0.0, 0.0, 0.0};
  EXPECT_TRUE(yard.roster.someone_stands_on(area, 1.2)) << "on the load's point";
  area.pose = {-1.2, 0.0, 0.0};  // its approach point, 1.2 m out along its yaw, is where fl1 stands
  EXPECT_TRUE(yard.roster.someone_stands_on(area, 1.2));
  area.pose = {3.0, 3.0, 0.0};
  EXPECT_FALSE(yard.roster.someone_stands_on(area, 1.2));
}

}  // namespace
}  // namespace fleet::orders
