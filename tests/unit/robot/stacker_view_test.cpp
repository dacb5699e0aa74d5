// What a stacker shows of a docking for the web view (Robot::docking_view): its two targets and
// the pallet its cameras detect while it docks, nothing otherwise.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "robot/robot_factory.hpp"
#include "robot/stacker/stacker.hpp"
#include "test_paths.hpp"

using namespace fleet;
using robot::RobotEvent;

namespace {

/// config/sites/plant.yaml's fleets on maps/plant.yaml, with the pallets standing where the map
/// puts them at the start; traffic control off.
struct Plant {
  std::shared_ptr<const map::SiteMap> site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  config::FleetConfig config = [] {
    config::FleetConfig c = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
    c.settings.set("traffic.enabled", "false", "stacker_view_test");
    return c;
  }();
  std::map<int, geometry::Pose2> loads;

  Plant() {
    int id = 1;
    for (const auto& area : site->site.loading_areas) {
      if (area.pallet_at_start) loads[id++] = area.pose;
    }
  }

  std::unique_ptr<robot::Robot> make(const std::string& fleet_id, const std::string& home_id) const {
    const auto fleet =
        std::find_if(config.fleets.begin(), config.fleets.end(), [&](const auto& f) { return f.id == fleet_id; });
    return robot::make_robot(*fleet, config, site, site->site.find_home(home_id)->pose, 3, 1);
  }

  task::TaskOrder transport(const std::string& from, const std::string& to) const {
    task::TaskOrder o;
    o.order_id = "7";
    o.pick_area_id = from;
    o.pick_area = site->site.find_area(from)->pose;
    o.drop_area_id = to;
    o.drop_area = site->site.find_area(to)->pose;
    return o;
  }
};

/// `along` metres from `pose` along its yaw.
geometry::Vec2 ahead_of(const geometry::Pose2& pose, double along) {
  return pose.position() + along * geometry::Vec2{std::cos(pose.yaw), std::sin(pose.yaw)};
}

}  // namespace

TEST(StackerView, ShowsItsTargetsAndTheDetectedPalletWhileDockingAndNothingOtherwise) {
  Plant plant;
  auto stacker = plant.make("stackers", "PT2");
  ASSERT_NE(dynamic_cast<robot::Stacker*>(stacker.get()), nullptr);
  stacker->set_standing_loads(plant.loads);
  EXPECT_TRUE(stacker->docking_view().empty()) << "parked in its bay";
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG5", "EX3"), &why)) << why;
  const geometry::Pose2 fg5 = plant.site->site.find_area("FG5")->pose;
  const control::DockingParams docking;

  int steps = 0;
  const auto run_while = [&](const std::string& state, auto&& each_step) {
    for (; steps < 20 * 900 && stacker->status().task_state == state; ++steps) {
      stacker->step();
      for (const auto& e : stacker->take_events()) {
        if (e.kind == RobotEvent::Kind::kFailed) FAIL() << e.text;
        if (e.kind == RobotEvent::Kind::kLifted) plant.loads.erase(e.load_id);
        if (e.kind == RobotEvent::Kind::kDone) plant.loads[e.load_id] = e.load_pose;
      }
      stacker->set_standing_loads(plant.loads);
      each_step();
    }
  };
  int shown_off_docking = 0;
  const auto count_shown = [&] {
    const bool driving = stacker->status().task_state == "TO_PICK" || stacker->status().task_state == "TO_DROP";
    shown_off_docking += driving && !stacker->docking_view().empty() ? 1 : 0;
  };
  run_while("TO_PICK", count_shown);
  ASSERT_EQ(stacker->status().task_state, "DOCKING");
  EXPECT_EQ(shown_off_docking, 0) << "steps on its way to the pallet that showed a docking";

  // Target 2 stands off the pallet's entry face on its axis, target 1 further out and along the
  // row [Stacker thesis, sections 6.3.1-6.3.2]; the estimate they are placed by errs by centimetres.
  const double target2_out = 0.5 * docking.pallet.depth + docking.target2_standoff;
  const double targets_apart = std::hypot(docking.target1_offset, docking.target1_extra_standoff);
  int with_targets = 0, without_targets = 0, with_pallet = 0;
  run_while("DOCKING", [&] {
    if (stacker->status().task_state != "DOCKING") return;
    const robot::DockingView view = stacker->docking_view();
    if (view.targets.size() != 2) {
      ++without_targets;
      return;
    }
    ++with_targets;
    EXPECT_LT(geometry::distance(view.targets[1], ahead_of(fg5, target2_out)), 0.15);
    EXPECT_NEAR(geometry::distance(view.targets[0], view.targets[1]), targets_apart, 0.01);
    if (!view.detected_pallet) return;
    ++with_pallet;
    EXPECT_LT(geometry::distance(view.detected_pallet->position(), fg5.position()), 0.15);
    EXPECT_LT(std::abs(geometry::angle_diff(view.detected_pallet->yaw, fg5.yaw)), 0.1);
  });
  ASSERT_EQ(stacker->status().task_state, "LIFTING") << stacker->status().detail;
  EXPECT_EQ(without_targets, 0) << "steps of the docking without its two targets";
  EXPECT_GT(with_targets, 20 * 10) << "steps of the docking showing its targets";
  EXPECT_GT(with_pallet, 20 * 5) << "steps of the docking showing a detected pallet";
  EXPECT_TRUE(stacker->docking_view().empty()) << "docked, lifting";

  // Putting the carried pallet down it docks to the place, where its cameras look for nothing.
  run_while("LIFTING", [] {});
  run_while("TO_DROP", count_shown);
  ASSERT_EQ(stacker->status().task_state, "PLACING");
  EXPECT_EQ(shown_off_docking, 0) << "steps on its way to the drop that showed a docking";
  int placing_with_targets = 0, placing_with_pallet = 0;
  run_while("PLACING", [&] {
    if (stacker->status().task_state != "PLACING") return;
    const robot::DockingView view = stacker->docking_view();
    placing_with_targets += view.targets.size() == 2 ? 1 : 0;
    placing_with_pallet += view.detected_pallet ? 1 : 0;
  });
  EXPECT_GT(placing_with_targets, 20 * 10);
  EXPECT_EQ(placing_with_pallet, 0);
  EXPECT_EQ(stacker->status().task_state, "LOWERING") << stacker->status().detail;
  EXPECT_TRUE(stacker->docking_view().empty());
}

TEST(StackerView, OtherRobotTypesShowNoDocking) {
  Plant plant;
  for (const auto& fleet : plant.config.fleets) {
    if (fleet.robot_type == "stacker") continue;
    auto robot = plant.make(fleet.id, fleet.robots.front().home);
    robot->set_standing_loads(plant.loads);
    for (int i = 0; i < 20; ++i) robot->step();
    EXPECT_TRUE(robot->docking_view().empty()) << fleet.id;
  }
}
