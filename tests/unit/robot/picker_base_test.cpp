// The picker's base on the plant: the forklift software without forks on the Summit-XLS, localised by the
// rack markers and wheel odometry [Picker thesis, section 4.2.9].
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>

#include "config/fleet_config.hpp"
#include "road_to_itself.hpp"
#include "robot/forklift/forklift.hpp"
#include "robot/robot_factory.hpp"
#include "test_paths.hpp"

using namespace fleet;
using robot::RobotEvent;

namespace {

struct PlantPicker {
  std::shared_ptr<const map::SiteMap> site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));

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

TEST(PickerBase, DrivesFromItsStallIntoTheRackAisleOnMarkersAndOdometry) {
  const PlantPicker plant;
  auto picker = plant.make("PP1");
  EXPECT_EQ(picker->status().footprint.length, 0.65);
  // Where the server sends a move to a loading area: the road in front of it, facing it.
  const auto target = plant.site->site.find_area("RB3")->approach_pose(plant.site->site.approach_distance);
  ASSERT_TRUE(picker->submit({"1", "", {}, "RB3", target, orders::OrderKind::kMove}, nullptr));
  bool done = false;
  double worst = 0.0;
  while (!done && picker->status().time < 150.0) {
    test::grant_everything(*picker);
    picker->step();
    worst =
        std::max(worst, geometry::distance(picker->status().estimate.position(), picker->status().truth.position()));
    for (const auto& e : picker->take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      done = done || e.kind == RobotEvent::Kind::kDone;
    }
  }
  ASSERT_TRUE(done) << picker->status().task_state << " (" << picker->status().detail << ") at "
                    << picker->status().truth.x << ", " << picker->status().truth.y;
  EXPECT_LT(geometry::distance(picker->status().truth.position(), target.position()), 0.15);
  EXPECT_GT(picker->status().truth.y, 10.2 + 0.25) << "in the aisle, clear of the rack face";
  std::cout << "picker: PP1 -> RB3 in " << picker->status().time << " s sim, estimate off by " << worst * 100.0
            << " cm at worst\n";
  EXPECT_LT(worst, 0.15) << "the estimate stays within 15 cm all the way, 30 m and four turns";
  EXPECT_GT(picker->status().localization_score, 0.3);
}

// A tour of two lines [Picker thesis, section 5.3.3.1.1, beyond its one box per job]: to RB1 and
// RB3 in the upper rack aisle, one box each onto the tray, then down to the packing station PS1.
TEST(PickerBase, DrivesAPickTourPicksEachLinesBoxesAndPutsThemDownAtThePackingStation) {
  const PlantPicker plant;
  auto picker = plant.make("PP1");
  const auto& site = plant.site->site;
  task::TaskOrder tour{
      "3", "RB1", site.find_area("RB1")->pose, "PS1", site.find_area("PS1")->pose, orders::OrderKind::kPick};
  tour.items = {{"RB1", site.find_area("RB1")->pose, "A1", 1}, {"RB3", site.find_area("RB3")->pose, "A3", 1}};
  std::string why;
  ASSERT_TRUE(picker->submit(tour, &why)) << why;
  std::set<std::string> states;
  bool done = false;
  double picking_s = 0.0, dropping_s = 0.0;
  while (!done && picker->status().time < 600.0) {
    test::grant_everything(*picker);
    picker->step();
    const std::string state = picker->status().task_state;
    states.insert(state);
    if (state == "PICK_ITEMS") picking_s += picker->step_period();
    if (state == "DROP_ITEMS") {
      dropping_s += picker->step_period();
      // Side-on beside the packing pallet, within the arm's reach of it.
      ASSERT_LT(geometry::distance(picker->status().truth.position(), {7.825, 4.1}), 0.15);
    }
    for (const auto& e : picker->take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      done = done || e.kind == RobotEvent::Kind::kDone;
    }
  }
  ASSERT_TRUE(done) << picker->status().task_state << " (" << picker->status().detail << ") at "
                    << picker->status().truth.x << ", " << picker->status().truth.y;
  for (const char* s : {"TRACK_PATH", "PICK_ITEMS", "DROP_ITEMS"}) EXPECT_TRUE(states.contains(s)) << s;
  // Two boxes: each located, picked and set on the tray, then taken off and put down.
  EXPECT_GT(picking_s, 20.0);
  EXPECT_GT(dropping_s, 20.0);
  std::cout << "picker tour: 2 lines, 2 boxes in " << picker->status().time << " s sim; arm " << picking_s
            << " s picking, " << dropping_s << " s dropping\n";
}

// A loader's walk (docs/loader.md): the boxes go on the pallet of the transporter
// behind it, a stop only once the order's update releases it, and the order ends at the last
// place, with no drive to a packing station.
TEST(PickerBase, AsALoaderSetsEachReleasedStopsBoxesBehindItAndEndsAtTheLastPlace) {
  const PlantPicker plant;
  auto picker = plant.make("PP1");
  const auto& site = plant.site->site;
  task::TaskOrder walk{"4", "RB1", site.find_area("RB1")->pose, "", {}, orders::OrderKind::kPick};
  walk.items = {{"RB1", site.find_area("RB1")->pose, "A1", 2}, {"RB3", site.find_area("RB3")->pose, "A3", 1}};
  walk.loader = true;
  walk.released = 1;
  walk.pallet = 1;
  std::string why;
  ASSERT_TRUE(picker->submit(walk, &why)) << why;
  bool done = false, waited = false, updated = false;
  double picking_s = 0.0, waiting_s = 0.0, untold_s = 0.0;
  std::set<std::string> states;
  while (!done && picker->status().time < 600.0) {
    test::grant_everything(*picker);
    picker->step();
    const std::string state = picker->status().task_state;
    states.insert(state);
    const bool at_first = geometry::distance(picker->status().truth.position(), {34.2, 10.6}) < 0.15;
    if (state == "WAITING" && picking_s > 0.0 && !updated) {
      // Its pallet moves up behind the second stop: the loader stands where it is meanwhile.
      ASSERT_TRUE(at_first) << "it waits at the first place, not at the second";
      waited = true;
      waiting_s += picker->step_period();
      if (waiting_s > 10.0) {
        // The pallet stands behind the second stop: the update releases it.
        task::TaskOrder update = walk;
        update.released = 2;
        ASSERT_TRUE(picker->submit(update, &why)) << why;
        updated = true;
      }
    } else if (state == "PICK_ITEMS") {
      // Its detail says the arm works (the stall watch takes that for progress), from the step
      // after the state changed on.
      if (picking_s > 0.0 && !picker->status().detail.starts_with("arm ")) untold_s += picker->step_period();
      picking_s += picker->step_period();
    }
    for (const auto& e : picker->take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      done = done || e.kind == RobotEvent::Kind::kDone;
    }
  }
  ASSERT_TRUE(done) << picker->status().task_state << " (" << picker->status().detail << ")";
  EXPECT_TRUE(waited);
  EXPECT_GE(waiting_s, 10.0);
  EXPECT_FALSE(states.contains("DROP_ITEMS")) << "no packing station";
  EXPECT_LT(geometry::distance(picker->status().truth.position(), {41.2, 10.6}), 0.5) << "it ends at RB3";
  // Three boxes, each located, picked and set on the pallet once.
  EXPECT_GT(picking_s, 3 * 5.0);
  EXPECT_LT(untold_s, 1.0) << "seconds of arm work its detail did not tell";
  std::cout << "picker as a loader: 3 boxes at 2 places, arm " << picking_s << " s, waited " << waiting_s << " s\n";
}

TEST(PickerBase, TakesNoTransports) {
  const PlantPicker plant;
  auto picker = plant.make("PP2");
  EXPECT_EQ(picker->refusal(orders::OrderKind::kTransport), "a picker has no forks");
  EXPECT_EQ(picker->refusal(orders::OrderKind::kPick), "");
  EXPECT_EQ(picker->refusal(orders::OrderKind::kMove), "");
  std::string why;
  const auto& area = plant.site->site.find_area("RB1")->pose;
  EXPECT_FALSE(picker->submit({"2", "RB1", area, "PS1", plant.site->site.find_area("PS1")->pose}, &why));
  EXPECT_EQ(why, "a picker has no forks");
}

}  // namespace

// Tours one after the other as the automatic orders send them, from racks in the upper and the
// lower aisles to packing stations on both sides of the packing area.
TEST(PickerBase, KeepsItsEstimateTourAfterTourAcrossThePlant) {
  const PlantPicker plant;
  auto picker = plant.make("PP1");
  const auto& site = plant.site->site;
  const std::vector<std::pair<std::string, std::string>> tours{
      {"RB5", "PS2"}, {"RB9", "PS4"}, {"RB15", "PS6"}, {"RB2", "PS8"}, {"RB11", "PS3"}};
  double worst = 0.0;
  std::string worst_where;
  int n = 0;
  for (const auto& [from, to] : tours) {
    const auto* rack = site.find_area(from);
    task::TaskOrder tour{std::to_string(++n), from, rack->pose, to, site.find_area(to)->pose, orders::OrderKind::kPick};
    tour.items = {{from, rack->pose, rack->boxes->item, 1}};
    std::string why;
    ASSERT_TRUE(picker->submit(tour, &why)) << why;
    bool done = false;
    const double started = picker->status().time;
    while (!done && picker->status().time < started + 400.0) {
      test::grant_everything(*picker);
      picker->step();
      const double error = geometry::distance(picker->status().estimate.position(), picker->status().truth.position());
      if (error > worst) {
        worst = error;
        worst_where = from + " -> " + to + " " + picker->status().task_state + " at (" +
                      std::to_string(picker->status().truth.x) + ", " + std::to_string(picker->status().truth.y) +
                      "), estimate (" + std::to_string(picker->status().estimate.x) + ", " +
                      std::to_string(picker->status().estimate.y) + ")";
      }
      for (const auto& e : picker->take_events()) {
        ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << from << " -> " << to << ": " << e.text;
        done = done || e.kind == RobotEvent::Kind::kDone;
      }
    }
    ASSERT_TRUE(done) << from << " -> " << to << ": " << picker->status().task_state << " (" << picker->status().detail
                      << ")";
  }
  std::cout << "picker: 5 tours, estimate off by " << worst * 100.0 << " cm at worst: " << worst_where << "\n";
  EXPECT_LT(worst, 0.5) << "worst " << worst_where;
}
