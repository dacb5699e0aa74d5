#include "emulation/emulated_robot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "geometry/polygon.hpp"
#include "map/site_map.hpp"
#include "test_paths.hpp"

namespace fleet::emulation {
namespace {

using geometry::Pose2;

const map::SiteMap& warehouse() {
  static const map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/warehouse.yaml"));
  return site;
}

/// One emulated robot and a stand-in for the traffic manager that grants each route up to
/// `granted` metres from its first point (the server's TrafficControl is tested with agents).
struct Yard {
  std::shared_ptr<const map::RoadGraph> graph = std::make_shared<map::RoadGraph>(warehouse().graph.graph);
  EmulatedRoutes routes{graph};
  std::vector<EmulatedRobot> robots;
  std::vector<EmulatedEvent> events;
  double granted = 1e9;
  double now = 0.0;

  void add(const std::string& home_id) {
    const map::Home* home = warehouse().site.find_home(home_id);
    std::string id = "r";
    id += std::to_string(robots.size() + 1);
    robots.emplace_back(id, home->pose, EmulationParams{}, 1000 * (robots.size() + 1));
  }

  void step() {
    for (auto& r : robots) {
      const robot::TrafficRoute route = r.traffic_route();
      if (!route.points.empty()) {
        robot::TrafficPermit permit;
        permit.version = route.version;
        // The last point within `granted` metres, as the manager grants up to a point.
        double along = 0.0;
        permit.granted_index = 0;
        for (std::size_t i = 1; i < route.points.size(); ++i) {
          const auto& a = graph->points[static_cast<std::size_t>(route.points[i - 1])];
          const auto& b = graph->points[static_cast<std::size_t>(route.points[i])];
          along += std::hypot(b.x - a.x, b.y - a.y);
          if (along > granted + 1e-9) break;
          permit.granted_index = static_cast<int>(i);
          permit.granted_distance = along;
        }
        r.grant(permit);
      }
      r.step(now, routes);
      for (auto& e : r.take_events()) events.push_back(e);
    }
    now += 0.05;
  }
};

EmulatedOrder transport(std::int64_t id, const std::string& from, const std::string& to, int load) {
  const auto& site = warehouse().site;
  return {id, orders::OrderKind::kTransport, from, site.find_area(from)->pose, to, site.find_area(to)->pose, load};
}

TEST(EmulatedRobot, RunsATransportThroughTheAgentsPhasesAndComesHome) {
  Yard yard;
  yard.add("H1");
  EXPECT_EQ(yard.robots[0].submit(transport(7, "A1", "A20", 3)), "");
  EXPECT_NE(yard.robots[0].submit(transport(8, "A3", "A4", 4)).find("busy with order 7"), std::string::npos);
  for (int i = 0; i < 20 * 600 && yard.robots[0].task_state() != "IDLE"; ++i) yard.step();
  std::vector<std::string> phases;
  const EmulatedEvent* done = nullptr;
  for (const auto& e : yard.events) {
    if (e.kind == EmulatedEvent::Kind::kPhase) phases.push_back(e.phase);
    if (e.kind == EmulatedEvent::Kind::kDone) done = &e;
  }
  EXPECT_EQ(phases, (std::vector<std::string>{"TO_PICK", "PICKING", "TO_DROP", "DROPPING"}));
  ASSERT_NE(done, nullptr);
  EXPECT_EQ(done->order_id, 7);
  EXPECT_EQ(done->load_id, 3);
  EXPECT_EQ(yard.events.back().kind, EmulatedEvent::Kind::kHome);
  const Pose2 home = warehouse().site.find_home("H1")->pose;
  EXPECT_NEAR(yard.robots[0].pose().x, home.x, 1e-6);
  EXPECT_NEAR(yard.robots[0].pose().y, home.y, 1e-6);
  EXPECT_EQ(yard.robots[0].carried_load(), -1);
}

TEST(EmulatedRobot, StandsUntilTheManagerGrantsTheRoad) {
  Yard yard;
  yard.add("H1");
  ASSERT_EQ(yard.robots[0].submit(transport(1, "A1", "A2", 1)), "");
  const Pose2 start = yard.robots[0].pose();
  // Planned, but never granted: the route is reported and the robot does not move.
  for (int i = 0; i < 40; ++i) yard.robots[0].step(0.05 * i, yard.routes);
  EXPECT_FALSE(yard.robots[0].traffic_route().points.empty());
  EXPECT_DOUBLE_EQ(yard.robots[0].pose().x, start.x);
  EXPECT_DOUBLE_EQ(yard.robots[0].pose().y, start.y);
  EXPECT_EQ(yard.robots[0].speed(), 0.0);
}

TEST(EmulatedRobot, StopsWhereItsGrantEnds) {
  Yard yard;
  yard.add("H1");
  yard.granted = 3.0;
  ASSERT_EQ(yard.robots[0].submit(transport(1, "A9", "A27", 2)), "");
  for (int i = 0; i < 20 * 60; ++i) yard.step();
  const robot::TrafficRoute route = yard.robots[0].traffic_route();
  EXPECT_LE(route.progress, 3.0);  // at the last graph point granted, within 0.5 m of 3 m
  EXPECT_GT(route.progress, 2.5);
  EXPECT_EQ(yard.robots[0].task_state(), "WAITING");
  EXPECT_EQ(yard.robots[0].speed(), 0.0);
  yard.granted = 1e9;  // the road ahead freed: it drives on to the pick
  for (int i = 0; i < 20 * 60 && yard.robots[0].task_state() != "PICK_PALLET"; ++i) yard.step();
  EXPECT_EQ(yard.robots[0].task_state(), "PICK_PALLET");
  EXPECT_NEAR(yard.robots[0].pose().x, warehouse().site.find_area("A9")->pose.x, 1e-6);
}

TEST(EmulatedRobot, AWithdrawnOrderSendsItHomeUnlessItCarriesTheLoad) {
  Yard yard;
  yard.add("H1");
  ASSERT_EQ(yard.robots[0].submit(transport(1, "A1", "A2", 5)), "");
  for (int i = 0; i < 20; ++i) yard.step();
  EXPECT_TRUE(yard.robots[0].withdraw());
  EXPECT_FALSE(yard.robots[0].order().has_value());
  EXPECT_EQ(yard.robots[0].submit({2, orders::OrderKind::kPick, "A1", {}, "A2", {}, -1}),
            "an emulated robot picks no items");
}

}  // namespace
}  // namespace fleet::emulation
