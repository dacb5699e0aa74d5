#include "robot/robot_factory.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "test_paths.hpp"

namespace fleet::robot {
namespace {

std::shared_ptr<const map::SiteMap> table_a() {
  static const auto site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/table_a.yaml")));
  return site;
}

TEST(RobotFactory, BuildsTheRobotOfTheFleetsTypeWithItsProfile) {
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  config::FleetSpec fleet = config.fleets.front();
  ASSERT_EQ(fleet.robot_type, "forklift");
  fleet.footprint = {0.30, 0.20};
  const auto home = table_a()->site.find_home("H1")->pose;
  const std::unique_ptr<Robot> robot = make_robot(fleet, config, table_a(), home, 1, 1);
  ASSERT_NE(robot, nullptr);
  EXPECT_DOUBLE_EQ(robot->footprint().length, 0.30);
  EXPECT_DOUBLE_EQ(robot->footprint().width, 0.20);
  EXPECT_LT(geometry::distance(robot->truth().position(), home.position()), 1e-9);
  EXPECT_EQ(robot->task_state(), "IDLE");
  EXPECT_EQ(robot->refusal(orders::OrderKind::kTransport), "");
  EXPECT_NE(robot->refusal(orders::OrderKind::kPick), "") << "a forklift has no arm";
}

TEST(RobotFactory, AnUnknownTypeIsNamedWithTheKnownOnes) {
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  config::FleetSpec fleet = config.fleets.front();
  fleet.robot_type = "crane";
  try {
    make_robot(fleet, config, table_a(), table_a()->site.find_home("H1")->pose, 1, 1);
    FAIL() << "a crane was built";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'crane'"), std::string::npos) << what;
    EXPECT_NE(what.find("forklift"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace fleet::robot
