#include "robot/robot_factory.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "test_paths.hpp"
#include "vehicle/vehicle_types.hpp"

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
  EXPECT_DOUBLE_EQ(robot->status().footprint.length, 0.30);
  EXPECT_DOUBLE_EQ(robot->status().footprint.width, 0.20);
  EXPECT_LT(geometry::distance(robot->status().truth.position(), home.position()), 1e-9);
  EXPECT_EQ(robot->status().task_state, "IDLE");
  EXPECT_EQ(robot->refusal(orders::OrderKind::kTransport), "");
  EXPECT_NE(robot->refusal(orders::OrderKind::kPick), "") << "a forklift has no arm";
}

TEST(RobotFactory, EveryTypeOfTheTableBuildsAndRefusesExactlyTheOrdersItsDataHasNoActionsFor) {
  // The two halves of a type (its data, read by config and the server, and its software, built
  // here) come from one line of core/robot/robot_types.def: they must agree on what it can do.
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  const auto plant =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  const auto has = [](const vehicle::RobotType& type, const std::string& action) {
    return std::find(type.possible_actions.begin(), type.possible_actions.end(), action) != type.possible_actions.end();
  };
  ASSERT_GE(vehicle::robot_types().size(), 4u);
  for (const vehicle::RobotType& type : vehicle::robot_types()) {
    SCOPED_TRACE(type.name);
    if (!type.agent_driven) continue;  // driven by fleet-vda5050, not built by the agent
    config::FleetSpec fleet = config.fleets.front();
    fleet.robot_type = type.name;
    fleet.profile = type.defaults;
    fleet.footprint = type.defaults.extent();
    const std::unique_ptr<Robot> robot = make_robot(fleet, config, plant, plant->site.find_home("PP1")->pose, 1, 1);
    ASSERT_NE(robot, nullptr);
    EXPECT_DOUBLE_EQ(robot->status().footprint.length, fleet.footprint.length);
    EXPECT_EQ(robot->refusal(orders::OrderKind::kTransport).empty(), has(type, "pick"));
    EXPECT_EQ(robot->refusal(orders::OrderKind::kPick).empty(), has(type, "pickItem"));
    EXPECT_EQ(robot->refusal(orders::OrderKind::kMove), "") << "every type drives";
  }
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

TEST(RobotFactory, AReachTrucksFollowerCutsABendAsTheCorePlacesItsBody) {
  // The coordination core's places hold what follower_drive sweeps: the agent's own follower,
  // which steers for a point one lookahead on and so leaves the route inside a bend.
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  const auto fleet = std::find_if(config.fleets.begin(), config.fleets.end(),
                                  [](const config::FleetSpec& f) { return f.id == "reach_trucks"; });
  ASSERT_NE(fleet, config.fleets.end());
  const control::FollowerParams follower = follower_params(config, *fleet);
  EXPECT_GT(follower.lookahead, 0.5) << "scaled with the 1.6 m body";
  std::vector<geometry::Vec2> path;
  for (int i = 0; i <= 6; ++i) path.push_back({0.5 * i, 0.0});
  for (int i = 1; i <= 6; ++i) path.push_back({3.0, 0.5 * i});
  const std::vector<geometry::Pose2> driven = follower_drive(follower, path);
  ASSERT_FALSE(driven.empty());
  double inside = 0.0, outside = 0.0;
  for (const geometry::Pose2& pose : driven) {
    if (pose.x < 3.0 && pose.y > 0.0) inside = std::max(inside, std::min(pose.y, 3.0 - pose.x));
    outside = std::max({outside, pose.x - 3.0, -pose.y});
  }
  EXPECT_GT(inside, 0.05) << "it cuts the bend on the inside";
  EXPECT_GT(outside, 0.05) << "and swings out past it";
  EXPECT_LT(std::max(inside, outside), follower.lookahead);
  EXPECT_LT(geometry::distance(driven.back().position(), path.back()), 0.1) << "and drives to the path's end";
}

}  // namespace
}  // namespace fleet::robot
