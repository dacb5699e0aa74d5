// The cart, the robot type added to the type table last: a fleet of carts on the plant drives
// from a stall into a rack aisle under the same software every wheeled type runs.
#include <gtest/gtest.h>

#include <algorithm>

#include "config/fleet_config.hpp"
#include "road_to_itself.hpp"
#include "robot/robot_factory.hpp"
#include "test_paths.hpp"
#include "vehicle/vehicle_types.hpp"

using namespace fleet;
using robot::RobotEvent;

namespace {

struct PlantCarts {
  std::shared_ptr<const map::SiteMap> site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));

  /// A fleet of carts with the type's own profile, homed where the pickers are.
  PlantCarts() {
    const auto pickers = std::find_if(config.fleets.begin(), config.fleets.end(),
                                      [](const config::FleetSpec& f) { return f.id == "pickers"; });
    config::FleetSpec carts = *pickers;
    carts.id = "carts";
    carts.robot_type = "cart";
    carts.profile = vehicle::find_robot_type("cart")->defaults;
    carts.footprint = carts.profile.extent();
    config.fleets.push_back(carts);
  }
  const config::FleetSpec& carts() const { return config.fleets.back(); }
};

TEST(Cart, IsInTheTypeTableWithADifferentialBaseAndNoHandling) {
  const vehicle::RobotType* cart = vehicle::find_robot_type("cart");
  ASSERT_NE(cart, nullptr) << vehicle::robot_type_names();
  EXPECT_EQ(cart->defaults.kinematics, vehicle::Kinematics::kDifferential);
  EXPECT_TRUE(cart->possible_actions.empty());
  EXPECT_NE(vehicle::robot_type_names().find("cart"), std::string::npos);
}

TEST(Cart, RefusesLoadsItCannotHandleAndDrivesAMoveOrderWithoutASidewaysCommand) {
  const PlantCarts plant;
  const auto home = plant.site->site.find_home("PP1")->pose;
  auto cart = robot::make_robot(plant.carts(), plant.config, plant.site, home, 1, 1);
  if (auto graph = robot::route_graph_for(plant.config, plant.carts(), *plant.site)) cart->set_site(plant.site, graph);
  EXPECT_EQ(cart->refusal(orders::OrderKind::kTransport), "a cart has no forks");
  EXPECT_EQ(cart->refusal(orders::OrderKind::kPick), "a cart performs no pickItem");
  EXPECT_EQ(cart->status().footprint.length, 0.60);

  const auto target = plant.site->site.find_area("RB3")->approach_pose(plant.site->site.approach_distance);
  ASSERT_TRUE(cart->submit({"1", "", {}, "RB3", target, orders::OrderKind::kMove}, nullptr));
  bool done = false;
  double sideways = 0.0;
  while (!done && cart->status().time < 150.0) {
    test::grant_everything(*cart);
    cart->step();
    sideways = std::max(sideways, std::abs(cart->status().command.vy));
    for (const auto& e : cart->take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      done = done || e.kind == RobotEvent::Kind::kDone;
    }
  }
  ASSERT_TRUE(done) << cart->status().task_state << " (" << cart->status().detail << ") at " << cart->status().truth.x
                    << ", " << cart->status().truth.y;
  EXPECT_LT(geometry::distance(cart->status().truth.position(), target.position()), 0.15);
  EXPECT_EQ(sideways, 0.0) << "a differential base has no sideways speed";
}

}  // namespace
