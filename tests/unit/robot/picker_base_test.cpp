// The picker's base on the plant: the forklift software without forks on the Summit-XLS, localised by the
// rack markers and wheel odometry [Picker thesis, section 4.2.9].
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "config/fleet_config.hpp"
#include "robot/forklift.hpp"
#include "robot/robot_factory.hpp"

using namespace fleet;
using robot::RobotEvent;

namespace {

struct PlantPicker {
  std::shared_ptr<const map::SiteMap> site =
      std::make_shared<const map::SiteMap>(map::load_site_map(FLEET_SOURCE_DIR "/maps/plant.yaml"));
  config::FleetConfig config = config::load_fleet_config(FLEET_SOURCE_DIR "/config/sites/plant.yaml");

  const config::FleetSpec& pickers() const {
    const auto it = std::find_if(config.fleets.begin(), config.fleets.end(),
                                 [](const config::FleetSpec& f) { return f.id == "pickers"; });
    if (it == config.fleets.end()) throw std::runtime_error("config/sites/plant.yaml has no pickers fleet");
    return *it;
  }

  std::unique_ptr<robot::Robot> make(const std::string& home) const {
    auto robot = robot::make_robot(pickers(), config, site, site->site.find_home(home)->pose, 1, 1);
    if (auto graph = robot::route_graph_for(config, pickers(), *site)) robot->set_site(site, graph);
    return robot;
  }
};

void grant_everything(robot::Robot& robot) {
  robot::TrafficPermit all_of_it;
  all_of_it.version = robot.route_version();
  all_of_it.granted_index = 1000;
  all_of_it.granted_distance = 1e9;
  robot.set_traffic_grant(all_of_it);
}

TEST(PickerBase, DrivesFromItsStallIntoTheRackAisleOnMarkersAndOdometry) {
  const PlantPicker plant;
  auto picker = plant.make("PP1");
  EXPECT_EQ(picker->footprint().length, 0.65);
  // Where the server sends a move to a loading area: the road in front of it, facing it.
  const auto target = plant.site->site.find_area("RB3")->approach_pose(plant.site->site.approach_distance);
  ASSERT_TRUE(picker->submit({"1", "", {}, "RB3", target, orders::OrderKind::kMove}, nullptr));
  bool done = false;
  double worst = 0.0;
  while (!done && picker->time() < 150.0) {
    grant_everything(*picker);
    picker->step();
    worst = std::max(worst, geometry::distance(picker->estimate().position(), picker->truth().position()));
    for (const auto& e : picker->take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      done = done || e.kind == RobotEvent::Kind::kDone;
    }
  }
  ASSERT_TRUE(done) << picker->task_state() << " (" << picker->detail() << ") at " << picker->truth().x << ", "
                    << picker->truth().y;
  EXPECT_LT(geometry::distance(picker->truth().position(), target.position()), 0.15);
  EXPECT_GT(picker->truth().y, 10.2 + 0.25) << "in the aisle, clear of the rack face";
  std::cout << "picker: PP1 -> RB3 in " << picker->time() << " s sim, estimate off by " << worst * 100.0
            << " cm at worst\n";
  EXPECT_LT(worst, 0.15) << "the estimate stays within 15 cm all the way, 30 m and four turns";
  EXPECT_GT(picker->localization_score(), 0.3);
}

TEST(PickerBase, TakesNoTransportsAndNoPicksItsArmCannotDoHere) {
  const PlantPicker plant;
  auto picker = plant.make("PP2");
  EXPECT_EQ(picker->refusal(orders::OrderKind::kTransport), "a picker has no forks");
  EXPECT_EQ(picker->refusal(orders::OrderKind::kPick), "a picker performs no pickItem");
  EXPECT_EQ(picker->refusal(orders::OrderKind::kMove), "");
  std::string why;
  const auto& area = plant.site->site.find_area("RB1")->pose;
  EXPECT_FALSE(picker->submit({"2", "RB1", area, "PS1", plant.site->site.find_area("PS1")->pose}, &why));
  EXPECT_EQ(why, "a picker has no forks");
}

}  // namespace
