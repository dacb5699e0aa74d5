// A robot on a road that a map switch takes away: it finds its way back onto the new map's roads.
#include <gtest/gtest.h>

#include "config/fleet_config.hpp"
#include "road_to_itself.hpp"
#include "robot/forklift/forklift.hpp"
#include "robot/robot_factory.hpp"
#include "test_paths.hpp"

using namespace fleet;
using robot::RobotEvent;

namespace {

std::shared_ptr<const map::SiteMap> table(const std::string& name) {
  return std::make_shared<const map::SiteMap>(
      map::load_site_map(map::site_path(fleet::test::source_path("/maps"), name)));
}

TEST(MapSwitch, ARobotOnARoadTheNewMapClosesDrivesBackOntoTheRoadsAndDoesItsOrder) {
  // Seen in the 4-agent soak: fl1, on its way to A5, had just turned from the crossing into
  // cross north when the server switched to table_a_north_closed, which has no cross north. On
  // the new map the ground under it was no free space, so no route could start there: it stood
  // with "no route" until the map was switched back.
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  config::apply_set_flag(config, "traffic.enabled=true");
  const config::FleetSpec& fleet = config.fleets.front();
  const auto before = table("table_a");
  const auto after = table("table_a_north_closed");
  auto robot = robot::make_robot(fleet, config, before, {1.5036, 1.9225, 1.6406}, 1, 1);
  robot->set_site(before, robot::route_graph_for(config, fleet, *before));
  const auto& a5 = before->site.find_area("A5")->pose;
  const auto& a4 = before->site.find_area("A4")->pose;
  robot->set_standing_loads({{3, a5}});  // the pallet on A5
  ASSERT_TRUE(robot->submit({"23", "A5", a5, "A4", a4}, nullptr));
  robot->set_site(after, robot::route_graph_for(config, fleet, *after));

  bool done = false;
  std::string no_route_at;
  while (!done && robot->status().time < 120.0) {
    test::grant_everything(*robot);
    robot->step();
    if (robot->status().detail == "no route" && no_route_at.empty()) no_route_at = std::to_string(robot->status().time);
    for (const auto& e : robot->take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      done = done || (e.kind == RobotEvent::Kind::kDone && e.order_id == "23");
    }
  }
  EXPECT_TRUE(done) << robot->status().task_state << " (" << robot->status().detail << ") at "
                    << robot->status().truth.x << ", " << robot->status().truth.y;
  EXPECT_TRUE(no_route_at.empty()) << "no route at " << no_route_at << " s";
}

}  // namespace
