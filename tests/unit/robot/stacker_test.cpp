#include "robot/stacker/stacker.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <stdexcept>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "orders/loader_job.hpp"
#include "outside_regions.hpp"
#include "plant_stacker.hpp"
#include "road_to_itself.hpp"
#include "robot/robot_factory.hpp"
#include "robot/stacker/stacker_job.hpp"
#include "task/transition_table.hpp"
#include "test_paths.hpp"
#include "traffic/conflict_zones.hpp"
#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_settings.hpp"
#include "vehicle/vehicle_types.hpp"

using namespace fleet;
using robot::RobotEvent;
using robot::Stacker;
using robot::StackerEvent;
using robot::StackerState;
using test::PlantStacker;

namespace {

constexpr StackerState kStates[] = {StackerState::kIdle,     StackerState::kToPick,  StackerState::kDocking,
                                    StackerState::kLifting,  StackerState::kToDrop,  StackerState::kPlacing,
                                    StackerState::kLowering, StackerState::kToPlace, StackerState::kToHome,
                                    StackerState::kParking,  StackerState::kHolding, StackerState::kToStand,
                                    StackerState::kStanding};
constexpr StackerEvent kEvents[] = {StackerEvent::kTransport, StackerEvent::kMove,       StackerEvent::kRouteEnded,
                                    StackerEvent::kDocked,    StackerEvent::kDockFailed, StackerEvent::kForksUp,
                                    StackerEvent::kForksDown, StackerEvent::kCancel,     StackerEvent::kMoveUp,
                                    StackerEvent::kHold,      StackerEvent::kStand,      StackerEvent::kStandBack,
                                    StackerEvent::kDrop};

TEST(StackerJob, EveryRowIsTheOnlyWayFromItsStateOnItsEventAndEveryStateIsReached) {
  const auto table = robot::stacker_transition_table();
  for (const auto& t : task::repeated_rows(table))
    ADD_FAILURE() << to_string(t.from) << " on " << to_string(t.event) << " listed twice";
  std::set<std::pair<int, int>> rows;
  for (const auto& t : table) {
    rows.insert({static_cast<int>(t.from), static_cast<int>(t.event)});
    EXPECT_EQ(robot::next_stacker_state(t.from, t.event), t.to);
  }
  for (StackerState s : kStates) {
    for (StackerEvent e : kEvents) {
      if (!rows.contains({static_cast<int>(s), static_cast<int>(e)})) {
        EXPECT_FALSE(robot::next_stacker_state(s, e)) << to_string(s) << " on " << to_string(e);
      }
    }
  }
  const auto reached = task::reachable_states(table, StackerState::kIdle);
  for (StackerState s : kStates) EXPECT_TRUE(reached.contains(s)) << to_string(s) << " unreachable";
}

TEST(StackerJob, APalletOnTheForksIsNeverCancelledNorLeftAtAFailedPlacing) {
  for (StackerState s :
       {StackerState::kLifting, StackerState::kToDrop, StackerState::kPlacing, StackerState::kLowering}) {
    EXPECT_FALSE(robot::next_stacker_state(s, StackerEvent::kCancel)) << to_string(s);
  }
  EXPECT_EQ(robot::next_stacker_state(StackerState::kPlacing, StackerEvent::kDockFailed), StackerState::kPlacing);
  EXPECT_EQ(robot::next_stacker_state(StackerState::kDocking, StackerEvent::kDockFailed), StackerState::kToHome);
}

TEST(StackerJob, WalksATransportFromItsBayBackToItsBay) {
  StackerState s = StackerState::kIdle;
  const std::pair<StackerEvent, StackerState> walk[] = {
      {StackerEvent::kTransport, StackerState::kToPick},   {StackerEvent::kRouteEnded, StackerState::kDocking},
      {StackerEvent::kDocked, StackerState::kLifting},     {StackerEvent::kForksUp, StackerState::kToDrop},
      {StackerEvent::kRouteEnded, StackerState::kPlacing}, {StackerEvent::kDocked, StackerState::kLowering},
      {StackerEvent::kForksDown, StackerState::kToHome},   {StackerEvent::kRouteEnded, StackerState::kParking},
      {StackerEvent::kDocked, StackerState::kIdle}};
  for (const auto& [event, to] : walk) {
    const auto next = robot::next_stacker_state(s, event);
    ASSERT_TRUE(next) << to_string(s) << " on " << to_string(event);
    EXPECT_EQ(*next, to);
    s = *next;
  }
  EXPECT_EQ(robot::stacker_phase(StackerState::kDocking), orders::OrderPhase::kPicking);
  EXPECT_EQ(robot::stacker_phase(StackerState::kPlacing), orders::OrderPhase::kDropping);
}

TEST(Stacker, DocksToAFinishedGoodsPalletCarriesItToExpeditionAndParksInItsBay) {
  PlantStacker plant;
  auto stacker = plant.make("PT2");
  const int pallet = plant.load_at.at("FG5");
  stacker->set_standing_loads(plant.loads);
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG5", "EX3"), &why)) << why;
  std::vector<RobotEvent> events;
  bool home = false;
  std::set<std::string> states;
  for (int i = 0; i < 20 * 900 && !home; ++i) {
    stacker->step();
    states.insert(stacker->status().task_state);
    for (auto& e : stacker->take_events()) {
      if (e.kind == RobotEvent::Kind::kFailed) FAIL() << "failed: " << e.text << " in " << stacker->status().task_state;
      if (e.kind == RobotEvent::Kind::kLifted) plant.loads.erase(e.load_id);
      if (e.kind == RobotEvent::Kind::kDone) plant.loads[e.load_id] = e.load_pose;
      home = home || e.kind == RobotEvent::Kind::kHome;
      if (e.kind != RobotEvent::Kind::kState && e.kind != RobotEvent::Kind::kPhase) events.push_back(e);
    }
    stacker->set_standing_loads(plant.loads);
  }
  ASSERT_TRUE(home) << "not home after 900 s; state " << stacker->status().task_state << ", detail '"
                    << stacker->status().detail << "', rear axle at (" << stacker->rear_axle().x << ", "
                    << stacker->rear_axle().y << ")";
  ASSERT_EQ(events.size(), 3u);
  EXPECT_EQ(events[0].kind, RobotEvent::Kind::kLifted);
  EXPECT_EQ(events[0].load_id, pallet);
  EXPECT_EQ(events[1].kind, RobotEvent::Kind::kDone);
  EXPECT_EQ(events[1].load_id, pallet);
  // The pallet stands on its expedition place: within the docking's own accuracy of it.
  const geometry::Pose2 ex3 = plant.site->site.find_area("EX3")->pose;
  EXPECT_LT(geometry::distance(events[1].load_pose.position(), ex3.position()), 0.05);
  EXPECT_LT(std::abs(geometry::angle_diff(events[1].load_pose.yaw, ex3.yaw)), 0.02);
  // Back in its bay, facing the aisle.
  const geometry::Pose2 bay = plant.site->site.find_home("PT2")->pose;
  EXPECT_LT(geometry::distance(stacker->status().truth.position(), bay.position()), 0.05);
  EXPECT_LT(std::abs(geometry::angle_diff(stacker->status().truth.yaw, bay.yaw)), 0.02);
  for (const char* s : {"TO_PICK", "DOCKING", "LIFTING", "TO_DROP", "PLACING", "LOWERING", "GO_HOME", "PARKING"}) {
    EXPECT_TRUE(states.contains(s)) << s;
  }
}

TEST(Stacker, DocksOnlyOnceTrafficHoldsTheAreaItsManoeuvreSweeps) {
  PlantStacker plant;
  auto stacker = plant.make("PT2", true);
  stacker->set_standing_loads(plant.loads);
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG5", "EX3"), &why)) << why;
  // The road is free: every route is granted whole. The area is answered "wait" for 30 s.
  const auto grant_all = [&] {
    const robot::TrafficRoute route = stacker->traffic_route();
    if (route.points.size() >= 2) stacker->set_traffic_grant(test::all_it_asks_for(route));
  };
  int step = 0;
  for (; step < 20 * 300 && stacker->status().task_state != "DOCKING"; ++step) {
    grant_all();
    stacker->step();
  }
  ASSERT_EQ(stacker->status().task_state, "DOCKING");
  const std::vector<geometry::Vec2> area = stacker->traffic_route().work_area;
  ASSERT_FALSE(area.empty());
  // It reaches over the pallet's place, and not behind the stacker where it stands: the robots
  // queued up there do not keep it from starting, and the run never backs towards them.
  const auto covers = [&](geometry::Vec2 p) {
    const auto [xs, xe] = std::minmax_element(area.begin(), area.end(), [](auto a, auto b) { return a.x < b.x; });
    const auto [ys, ye] = std::minmax_element(area.begin(), area.end(), [](auto a, auto b) { return a.y < b.y; });
    return p.x > xs->x && p.x < xe->x && p.y > ys->y && p.y < ye->y;
  };
  EXPECT_TRUE(covers(plant.site->site.find_area("FG5")->pose.position()));
  const geometry::Pose2 start = stacker->status().truth;
  const geometry::Vec2 behind = start.position() - 1.2 * geometry::Vec2{std::cos(start.yaw), std::sin(start.yaw)};
  EXPECT_FALSE(covers(behind)) << "the area reaches behind the stacker's fork tips";
  robot::TrafficPermit hold;
  hold.area = robot::TrafficPermit::Area::kWaiting;
  hold.blocked_by = {"fk1"};
  geometry::Pose2 stood;
  for (int i = 0; i < 20 * 30; ++i) {
    if (i == 20 * 2) stood = stacker->status().truth;  // stopped from the route's last metres by then
    stacker->set_traffic_grant(hold);
    stacker->step();
  }
  EXPECT_LT(geometry::distance(stacker->status().truth.position(), stood.position()), 1e-3) << "it moved into the area";
  EXPECT_EQ(stacker->status().task_state, "DOCKING");
  robot::TrafficPermit clear;
  clear.area = robot::TrafficPermit::Area::kClear;
  stacker->set_traffic_grant(clear);
  double back = 0.0;  // how far the centre came back along the lane from where it stood
  std::set<std::string> details;
  for (int i = 0; i < 20 * 120 && stacker->status().task_state == "DOCKING"; ++i) {
    stacker->step();
    details.insert(stacker->status().detail);
    const geometry::Vec2 d = stacker->status().truth.position() - stood.position();
    back = std::max(back, -(d.x * std::cos(stood.yaw) + d.y * std::sin(stood.yaw)));
  }
  EXPECT_EQ(stacker->status().task_state, "LIFTING") << stacker->status().detail;
  EXPECT_LT(back, 0.1) << "the docking run backed towards the robots behind";
  // Its detail tells where the docking stands.
  for (const char* phase : {"docking: to_target1", "docking: pivot", "docking: fork_in"}) {
    EXPECT_TRUE(details.contains(phase)) << phase;
  }
  EXPECT_TRUE(stacker->traffic_route().work_area.empty()) << "the area is let go once docked";
  // Docked, it asks traffic to keep clear the ways it may turn out by: to either side of the place.
  const geometry::Polygon keep_clear = traffic::convex_hull(stacker->traffic_route().keep_clear);
  ASSERT_GE(keep_clear.size(), 3u) << "no way out kept clear while docked";
  const geometry::Pose2 fg5 = plant.site->site.find_area("FG5")->pose;
  for (const double side : {-2.0, 2.0}) {
    EXPECT_TRUE(geometry::contains(keep_clear, {fg5.x + side, start.y})) << side << " m along the lane";
  }
  // Loaded, it asks for its way out onto the road with its route: from where it stands, turning
  // onto the lane, to past the route's first point. That lies in what it kept clear.
  for (int i = 0; i < 20 * 30 && stacker->traffic_route().points.empty(); ++i) stacker->step();
  const robot::TrafficRoute out = stacker->traffic_route();
  ASSERT_FALSE(out.points.empty()) << stacker->status().task_state;
  EXPECT_TRUE(out.keep_clear.empty()) << "on its way, it keeps nothing clear";
  const std::vector<geometry::Vec2> way_out = out.work_area;
  ASSERT_FALSE(way_out.empty()) << "no way out asked for";
  for (const auto& corner : way_out) {
    EXPECT_LT(geometry::convex_polygons_distance(
                  keep_clear, {corner, corner + geometry::Vec2{1e-3, 0.0}, corner + geometry::Vec2{0.0, 1e-3}}),
              0.15)
        << "corner (" << corner.x << ", " << corner.y << ") of the way out was not kept clear";
  }
  const auto in_hull = [&](geometry::Vec2 p) {
    return geometry::convex_polygons_overlap(traffic::convex_hull(way_out),
                                             {p, p + geometry::Vec2{1e-3, 0.0}, p + geometry::Vec2{0.0, 1e-3}});
  };
  EXPECT_TRUE(in_hull(stacker->status().estimate.position()));
  const auto& road = plant.site->graph.graph.points;
  const auto& first = road[static_cast<std::size_t>(out.points.front())];
  EXPECT_TRUE(in_hull({first.x, first.y}));
  // Granted, it drives out; on the road it asks for no area any more.
  for (int i = 0; i < 20 * 30; ++i) {
    grant_all();
    stacker->step();
  }
  EXPECT_TRUE(stacker->traffic_route().work_area.empty())
      << stacker->status().task_state << " " << stacker->status().detail;
}

TEST(Stacker, APalletNotWhereLogisticsSaysFailsTheOrderWithWhatTheCamerasSaw) {
  PlantStacker plant;
  auto stacker = plant.make("PT2");
  plant.loads.erase(plant.load_at.at("FG5"));  // the ledger says FG5; nothing stands there
  stacker->set_standing_loads(plant.loads);
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG5", "EX3"), &why)) << why;
  std::string failure;
  for (int i = 0; i < 20 * 600 && failure.empty(); ++i) {
    stacker->step();
    for (auto& e : stacker->take_events()) {
      if (e.kind == RobotEvent::Kind::kFailed) failure = e.text;
      EXPECT_NE(e.kind, RobotEvent::Kind::kLifted);
    }
  }
  EXPECT_NE(failure.find("docking at FG5: pallet not found"), std::string::npos) << failure;
  EXPECT_NE(failure.find("frames, last:"), std::string::npos) << failure;
  EXPECT_EQ(stacker->status().task_state, "GO_HOME");
  EXPECT_EQ(stacker->status().carried_load, -1);
}

TEST(Stacker, RefusesPickItemAndASecondOrder) {
  PlantStacker plant;
  auto stacker = plant.make("PT1");
  EXPECT_FALSE(stacker->refusal(orders::OrderKind::kPick).empty());
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG1", "EX1"), &why));
  task::TaskOrder second = plant.transport("FG3", "EX5");
  second.order_id = "8";
  EXPECT_FALSE(stacker->submit(second, &why));
  EXPECT_NE(why.find("busy with order 7"), std::string::npos) << why;
  // The same order again is an update of it; one that names its drop place has nothing to update.
  EXPECT_FALSE(stacker->submit(plant.transport("FG1", "EX3"), &why));
  EXPECT_EQ(why, "order 7 names its drop place already");
}

}  // namespace

TEST(Stacker, ItsDockingRunsStayInsideTheAreasTrafficHoldsForThem) {
  // Traffic holds the hull of the asked-for area and the body the stacker stands with; other
  // robots stop at its edge. A run that swung outside it would meet them.
  PlantStacker plant;
  auto stacker = plant.make("PT2", true);
  stacker->set_standing_loads(plant.loads);
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG9", "PK6"), &why)) << why;
  std::vector<geometry::Vec2> held;
  double outside = 0.0;
  std::string where;
  int areas = 0;
  for (int i = 0; i < 20 * 600 && stacker->status().task_state != "GO_HOME"; ++i) {
    const robot::TrafficRoute route = stacker->traffic_route();
    if (!route.work_area.empty() && route.points.size() < 2) {
      if (held.empty()) {
        ++areas;
        held = route.work_area;
        for (const auto& c : geometry::footprint_polygon(stacker->status().estimate, stacker->status().footprint))
          held.push_back(c);
      }
    } else {
      held.clear();
    }
    stacker->set_traffic_grant(test::all_it_asks_for(route));
    stacker->step();
    for (const auto& e : stacker->take_events()) {
      if (e.kind == RobotEvent::Kind::kLifted) plant.loads.erase(e.load_id);
      if (e.kind == RobotEvent::Kind::kDone) plant.loads[e.load_id] = e.load_pose;
    }
    stacker->set_standing_loads(plant.loads);
    if (held.empty()) continue;
    const geometry::Polygon hull = traffic::convex_hull(held);
    for (const auto& c : geometry::footprint_polygon(stacker->status().truth, stacker->status().footprint)) {
      const double d =
          geometry::convex_polygons_distance(hull, {c, c + geometry::Vec2{1e-4, 0.0}, c + geometry::Vec2{0.0, 1e-4}});
      if (d > outside) {
        outside = d;
        where = stacker->status().detail;
      }
    }
  }
  ASSERT_EQ(stacker->status().task_state, "GO_HOME") << stacker->status().detail;
  EXPECT_EQ(areas, 2) << "the docking at the pick place and at the drop place";
  EXPECT_LT(outside, 1e-3) << "its body left the held area by " << outside << " m (" << where << ")";
}

TEST(Stacker, ItsWayOutOfAFinishedGoodsPlaceIsNotHeldUpByTheStackerParkedBehindIt) {
  // Loaded at FG5 it drives out forwards onto the corridor's lane, its fork tips 0.7 m from the
  // stacker parked in PT2. Traffic holds that parked body, and the way out does not reach it.
  PlantStacker plant;
  auto stacker = plant.make("PT1", true);
  stacker->set_standing_loads(plant.loads);
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG5", "EX7"), &why)) << why;
  for (int i = 0; i < 20 * 600 && stacker->status().task_state != "TO_DROP"; ++i) {
    stacker->set_traffic_grant(test::all_it_asks_for(stacker->traffic_route()));
    stacker->step();
  }
  ASSERT_EQ(stacker->status().task_state, "TO_DROP") << stacker->status().detail;
  for (int i = 0; i < 20 * 30 && stacker->traffic_route().points.empty(); ++i) stacker->step();
  const robot::TrafficRoute out = stacker->traffic_route();
  ASSERT_FALSE(out.work_area.empty()) << "no way out asked for";
  const geometry::Polygon way_out = traffic::convex_hull(out.work_area);
  const geometry::Polygon parked =
      geometry::footprint_polygon(plant.site->site.find_home("PT2")->pose, stacker->status().footprint);
  ASSERT_GT(geometry::convex_polygons_distance(way_out, parked), 0.3);
  const config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  traffic::TrafficManager traffic(plant.site->graph.graph, traffic::configuration_from(config));
  const int stackers = traffic::vehicle_type_of(config, "stackers");
  traffic.set_robot_type(2, stackers);
  traffic.set_robot_type(4, stackers);
  ASSERT_TRUE(traffic.hold_body(2, parked, 0.0));
  EXPECT_TRUE(traffic.holders_in_area(4, way_out, {{2, parked}}).empty()) << "held up by the parked stacker";
  // A body standing in the way out does hold it up.
  const geometry::Polygon in_the_way =
      geometry::footprint_polygon({out.work_area.front().x, out.work_area.front().y, 0.0}, stacker->status().footprint);
  ASSERT_TRUE(traffic.hold_body(2, in_the_way, 0.0));
  EXPECT_EQ(traffic.holders_in_area(4, way_out, {{2, in_the_way}}), std::vector<int>{2});
}

namespace fleet::robot {
namespace {

/// Drives a stacker loaded at FG13 to WA1 and on its way home, with everything granted, while a
/// reach truck whose pose is `age` seconds old stands where the soak's rt1 waited, at the middle
/// aisle's north end: whether the stacker passes it on its turn into the aisle.
bool passes_reach_truck_at_the_junction(double age, std::string* why) {
  PlantStacker plant;
  auto stacker = plant.make("PT2", true);
  stacker->set_standing_loads(plant.loads);
  if (!stacker->submit(plant.transport("FG13", "WA1"), why)) return false;
  const Neighbour waiting{"rt1", {30.43, 24.38, -2.72}, {1.6, 0.9}, 0.0, age};
  const geometry::Polygon body = geometry::footprint_polygon(waiting.pose, waiting.footprint);
  bool going_home = false;
  double nearest = 1e9;
  for (int i = 0; i < 20 * 260; ++i) {
    stacker->set_traffic_grant(test::all_it_asks_for(stacker->traffic_route()));
    if (going_home) stacker->navigation().set_neighbours({waiting});
    stacker->step();
    stacker->take_events();
    going_home = going_home || stacker->status().task_state == "GO_HOME";
    if (!going_home) continue;
    nearest =
        std::min(nearest, geometry::convex_polygons_distance(
                              geometry::footprint_polygon(stacker->status().truth, stacker->status().footprint), body));
    // Down the middle aisle, past the junction.
    if (stacker->status().truth.y < 19.0 && stacker->status().truth.x > 27.0) {
      if (nearest < 0.3) *why = "passed within " + std::to_string(nearest) + " m";
      return nearest >= 0.3;
    }
  }
  *why = "stands at (" + std::to_string(stacker->status().truth.x) + ", " + std::to_string(stacker->status().truth.y) +
         ") in " + stacker->status().task_state + ": " + stacker->status().detail;
  return false;
}

}  // namespace

// The stacker's way home from WA1 turns into the middle aisle where a reach truck waits for it
// to pass. The stacker passes 0.4 m from it, also when the truck's pose arrives late (0.65 s
// old: a loaded host at time scale 5); a robot silent for 1.5 s may be anywhere within a metre,
// and the stacker waits.
TEST(Stacker, TurnsIntoAnAislePastARobotWaitingAtItsJunction) {
  std::string why;
  EXPECT_TRUE(passes_reach_truck_at_the_junction(0.0, &why)) << why;
  EXPECT_TRUE(passes_reach_truck_at_the_junction(0.65, &why)) << why;
  EXPECT_FALSE(passes_reach_truck_at_the_junction(1.5, &why)) << "a robot silent for 1.5 s was passed";
}

// Its pursuit cuts inside the tight bend from the aisle into the corridor and swings its front
// past the bend over the corridor's other lane; traffic reserves what that drive sweeps.
TEST(Stacker, TurningOutOfAnAisleItsBodyStaysInsideThePlacesTrafficReservesForIt) {
  const auto closed = std::make_shared<const map::SiteMap>(
      map::load_site_map(fleet::test::source_path("/maps/plant_middle_closed.yaml")));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  config.settings.set("traffic.enabled", "true", "stacker_test");
  const auto& fleet =
      *std::find_if(config.fleets.begin(), config.fleets.end(), [](const auto& f) { return f.id == "stackers"; });
  // In aisle 3, southbound.
  auto stacker = make_robot(fleet, config, closed, {29.13, 22.0, -std::numbers::pi / 2}, 3, 1);
  stacker->set_site(closed, route_graph_for(config, fleet, *closed));
  task::TaskOrder home;
  home.order_id = "8";
  home.kind = orders::OrderKind::kMove;
  home.drop_area_id = "PT3";
  home.drop_area = closed->site.find_home("PT3")->pose;
  std::string why;
  ASSERT_TRUE(stacker->submit(home, &why)) << why;
  const traffic::ConflictZones zones(closed->graph.graph, traffic::configuration_from(config).resources);
  const int type = traffic::vehicle_type_of(config, "stackers");
  std::vector<const geometry::Polygon*> reserved;
  double worst = 0.0;
  int turning = 0;
  for (int i = 0; i < 20 * 120 && stacker->status().truth.x > 24.0; ++i) {
    const robot::TrafficRoute route = stacker->traffic_route();
    if (reserved.empty() && route.points.size() >= 2) {
      for (int point : route.points) {
        for (const auto& region : zones.region(type, zones.place_of(point))) reserved.push_back(&region);
      }
    }
    stacker->set_traffic_grant(test::all_it_asks_for(route));
    stacker->step();
    stacker->take_events();
    // Through the turn from the aisle (x = 29.13) into the north lane (y = 17.85).
    const geometry::Pose2 at = stacker->status().truth;
    if (reserved.empty() || at.x < 26.0 || at.x > 30.0 || at.y > 19.5) continue;
    ++turning;
    const geometry::Polygon body = geometry::footprint_polygon(at, stacker->status().footprint);
    worst = std::max(worst, test::outside(body, reserved));
  }
  EXPECT_LT(stacker->status().truth.x, 24.0) << stacker->status().task_state << ": " << stacker->status().detail;
  EXPECT_GT(turning, 20);
  EXPECT_LT(worst, 0.01) << "the stacker's body left the places of its route by " << worst << " m";
}

}  // namespace fleet::robot

TEST(Stacker, SentToASidingOnItsWayItWaitsThereAndDocksOnlyAtThePallet) {
  // Seen in the plant soak: st2, on its way to dock at RB13, yielded on a siding in the north
  // cross aisle; at the siding's end it took its route for done and docked to the expedition
  // pallets beside it.
  PlantStacker plant;
  auto stacker = plant.make("PT2", true);
  stacker->set_standing_loads(plant.loads);
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("FG5", "EX3"), &why)) << why;
  const geometry::Vec2 bay = plant.site->site.find_home("PT2")->pose.position();
  std::vector<int> route;
  for (int step = 0; step < 20 * 60 && route.size() < 8; ++step) {
    const robot::TrafficRoute r = stacker->traffic_route();
    if (r.points.size() >= 2) {
      stacker->set_traffic_grant(test::all_it_asks_for(r));
      // On the aisle, out of its bay: the route ahead.
      if (geometry::distance(stacker->status().truth.position(), bay) > 3.0) route = r.points;
    }
    stacker->step();
  }
  ASSERT_GE(route.size(), 8u) << stacker->status().task_state << " (" << stacker->status().detail << ")";
  // The manager sends it to a siding: the next few points of its own route.
  robot::TrafficPermit siding;
  siding.version = stacker->traffic_route().version + 1;
  siding.route.assign(route.begin(), route.begin() + 5);
  siding.granted_index = 4;
  siding.granted_distance = 1e6;
  siding.siding = true;
  stacker->set_traffic_grant(siding);
  const auto& end = plant.site->graph.graph.points[static_cast<std::size_t>(route[4])];
  const double sent = stacker->status().time;
  while (stacker->status().time < sent + 25.0) {
    stacker->step();
    ASSERT_EQ(stacker->status().task_state, "TO_PICK") << stacker->status().detail;
  }
  EXPECT_LT(geometry::distance(stacker->rear_axle().position(), {end.x, end.y}), 0.3);
  EXPECT_EQ(stacker->traffic_route().version, siding.version) << "still waits on the siding";
  // Not called back, it plans its own way on after the siding's timeout and lifts FG5's pallet.
  int lifted = -1;
  std::optional<geometry::Vec2> docked_from;
  for (int step = 0; step < 20 * 300 && lifted < 0; ++step) {
    const robot::TrafficRoute r = stacker->traffic_route();
    if (r.points.size() >= 2 || !r.work_area.empty()) stacker->set_traffic_grant(test::all_it_asks_for(r));
    stacker->step();
    if (!docked_from && stacker->status().task_state == "DOCKING") docked_from = stacker->rear_axle().position();
    for (const auto& e : stacker->take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      if (e.kind == RobotEvent::Kind::kLifted) lifted = e.load_id;
    }
  }
  EXPECT_EQ(lifted, plant.load_at.at("FG5")) << stacker->status().task_state << " (" << stacker->status().detail << ")";
  ASSERT_TRUE(docked_from.has_value());
  EXPECT_GT(geometry::distance(*docked_from, {end.x, end.y}), 0.3) << "docked from the siding's end";
}

TEST(Stacker, OnItsRouteItNamesTheAreaItsDockingWillSweepSoNobodyIsGrantedIntoIt) {
  // Seen in the plant soak: a forklift was granted along the corridor up beside st3 as st3 reached
  // the end of its route to PK1; st3's docking area then held the forklift, whose way on st3's
  // body blocked, and both stood for good.
  PlantStacker plant;
  auto stacker = plant.make("PT2", true);
  stacker->set_standing_loads(plant.loads);
  std::string why;
  ASSERT_TRUE(stacker->submit(plant.transport("PK4", "EX3"), &why)) << why;
  std::vector<geometry::Vec2> arrival;
  for (int step = 0; step < 20 * 300 && stacker->status().task_state != "DOCKING"; ++step) {
    const robot::TrafficRoute r = stacker->traffic_route();
    if (r.points.size() >= 2) {
      stacker->set_traffic_grant(test::all_it_asks_for(r));
      arrival = r.arrival_area;
    }
    stacker->step();
  }
  ASSERT_EQ(stacker->status().task_state, "DOCKING");
  ASSERT_GE(arrival.size(), 3u) << "the route named no arrival area";
  const geometry::Polygon held = traffic::convex_hull(arrival);
  // What the docking asks traffic to hold lies inside what the route held, but for the
  // difference between the planned and the reached pose at the route's end.
  std::vector<geometry::Vec2> work;
  for (int step = 0; step < 20 && work.empty(); ++step) {
    work = stacker->traffic_route().work_area;
    stacker->step();
  }
  ASSERT_FALSE(work.empty());
  for (const auto& corner : work) {
    EXPECT_LT(geometry::convex_polygons_distance(
                  held, {corner, corner + geometry::Vec2{1e-3, 0.0}, corner + geometry::Vec2{0.0, 1e-3}}),
              0.15)
        << "corner (" << corner.x << ", " << corner.y << ") outside the arrival area";
  }
  // It reaches across the corridor's far lane, where the forklift stood.
  const geometry::Pose2 pk4 = plant.site->site.find_area("PK4")->pose;
  EXPECT_TRUE(geometry::contains(held, {pk4.x, 17.85}));
}
