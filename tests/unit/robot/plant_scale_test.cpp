#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "config/fleet_config.hpp"
#include "road_to_itself.hpp"
#include "robot/forklift/forklift.hpp"
#include "robot/robot_factory.hpp"
#include "sim/mecanum.hpp"
#include "test_paths.hpp"
#include "vehicle/vehicle_types.hpp"

using namespace fleet;
using robot::ForkliftConfig;
using robot::RobotEvent;

namespace {

vehicle::VehicleProfile plant_forklift() {
  // config/sites/plant.yaml, fleet `forklifts`.
  vehicle::VehicleProfile p;
  p.footprint = vehicle::rectangle(1.2, 0.8);
  p.max_speed = 1.2;
  p.max_acceleration = 0.5;
  p.max_yaw_rate = 1.0;
  return p;
}

/// Every value for_vehicle() sets, in one list, so two configurations compare field by field.
std::vector<double> scaled_values(const ForkliftConfig& c) {
  const auto& f = c.task.follower;
  const auto& a = c.task.search.approach;
  const auto& m = c.sim.forklift.mecanum;
  const auto& e = c.sim.ekf;
  return {c.sim.forklift.footprint.length,
          c.sim.forklift.footprint.width,
          m.wheel_radius,
          m.half_wheelbase,
          m.half_track,
          m.max_wheel_speed,
          c.sim.uwb.antenna_offset.x,
          e.antenna_offset.x,
          e.heading_init_distance,
          e.commanded_velocity_std[0],
          e.commanded_velocity_std[1],
          e.encoder_velocity_std[0],
          e.encoder_velocity_std[1],
          f.v_max,
          f.omega_max,
          f.lookahead,
          f.goal_tolerance,
          f.regulate_min_radius,
          f.obstacle_stop_distance,
          f.obstacle_slow_distance,
          f.regulated_min_speed,
          f.max_linear_accel,
          f.max_angular_accel,
          a.v_max,
          a.lookahead,
          a.goal_tolerance,
          c.task.geometry.camera_x,
          c.task.geometry.carry_x,
          c.task.geometry.marker_offset,
          c.task.search.standoff,
          c.task.search.match_radius,
          c.task.pick.v_minx,
          c.task.pick.v_miny,
          c.task.pick.drive_in_speed,
          c.task.pick.d_min,
          c.task.pick.d_tol,
          c.task.pick.timeout,
          c.task.place.lateral_tol,
          c.task.place.longitudinal_tol,
          c.task.place.vx_limit,
          c.task.place.vy_limit,
          c.task.place.v_floor,
          c.task.place.back_out_distance,
          c.task.place.back_out_speed,
          c.task.place.timeout,
          c.task.arrival_tolerance,
          c.camera.range_min,
          c.camera.range_max,
          c.camera.sigma_d,
          c.pallet_world.lift_lateral_tol,
          c.pallet_world.lift_depth_tol,
          c.grid_resolution,
          c.lidar.max_range,
          c.lidar.min_range,
          c.safety_gap,
          c.stop_distance,
          c.neighbour_margin,
          c.neighbour_max_speed,
          c.neighbour_max_reach,
          c.reported_tolerance,
          c.robot_height,
          c.anchor_shadow_margin,
          c.clearance_lookahead,
          c.clearance_sample,
          c.clearance_margin,
          c.temporary_size,
          c.safety_scan_range,
          c.escape_within,
          c.escape_speed,
          c.stop_moved,
          c.uwb_shadow_reach,
          c.siding_end_margin};
}

/// A robot of one of the plant's fleets on the plant's map (maps/plant.yaml,
/// config/sites/plant.yaml), made as the agent makes it: its fleet's software and route graph.
struct PlantRobot {
  std::shared_ptr<const map::SiteMap> site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  std::unique_ptr<robot::Robot> robot;

  std::unique_ptr<robot::Robot>& make(const std::string& fleet_id, const geometry::Pose2& pose) {
    const auto fleet = std::find_if(config.fleets.begin(), config.fleets.end(),
                                    [&](const config::FleetSpec& f) { return f.id == fleet_id; });
    if (fleet == config.fleets.end()) throw std::runtime_error("the plant has no fleet '" + fleet_id + "'");
    robot = robot::make_robot(*fleet, config, site, pose, 1, 1);
    if (auto graph = robot::route_graph_for(config, *fleet, *site)) robot->set_site(site, graph);
    return robot;
  }
};

}  // namespace

TEST(ForkliftForVehicle, TheTableProfileGivesExactlyTheDefaults) {
  const auto& table = vehicle::find_robot_type("forklift")->defaults;
  const auto mine = scaled_values(ForkliftConfig::for_vehicle(table));
  const auto defaults = scaled_values(ForkliftConfig::defaults());
  ASSERT_EQ(mine.size(), defaults.size());
  for (std::size_t i = 0; i < mine.size(); ++i) EXPECT_EQ(mine[i], defaults[i]) << "value " << i;
  EXPECT_TRUE(ForkliftConfig::for_vehicle(table).task.follower.smooth_lookahead);  // still the regulated follower
}

TEST(ForkliftForVehicle, ARealForkliftGetsItsSizeSpeedAndBrakingDistance) {
  const auto c = ForkliftConfig::for_vehicle(plant_forklift());
  // The camera sits at the front edge, the pallet seats ahead of it, as on the table.
  EXPECT_NEAR(c.task.geometry.camera_x, 0.48 * 1.2, 1e-12);
  EXPECT_GT(c.task.geometry.carried_marker_distance(), 0.0);
  EXPECT_LT(c.task.geometry.camera_x, 0.6);
  // The simulated body can reach the profile's top speed (the table body tops out at 0.3 m/s).
  const sim::MecanumKinematics body(c.sim.forklift.mecanum);
  EXPECT_NEAR(body.limits().max_linear, 1.2, 1e-9);
  EXPECT_GT(body.limits().max_angular, 1.0);
  // Lengths scale by 1.2 / 0.25.
  EXPECT_NEAR(c.task.follower.lookahead, 0.10 * 4.8, 1e-12);
  EXPECT_NEAR(c.safety_gap, 0.03 * 4.8, 1e-12);
  EXPECT_NEAR(c.grid_resolution, 0.02 * 4.8, 1e-12);
  // Slowing starts far enough to stop from 1.2 m/s at 80 % of 0.5 m/s^2, and the path is checked
  // that far ahead.
  const double braking = 1.2 * 1.2 / (2.0 * 0.8 * 0.5);
  EXPECT_NEAR(c.task.follower.obstacle_slow_distance, c.task.follower.obstacle_stop_distance + braking, 1e-12);
  EXPECT_GE(c.clearance_lookahead, c.task.follower.obstacle_slow_distance);
  // Manoeuvres run at most 4x the table's speeds (1.2 / 0.3), never above the vehicle's.
  EXPECT_NEAR(c.task.pick.v_minx, 0.03 * 4.0, 1e-12);
  EXPECT_LE(c.task.place.vx_limit, 1.2);
}

TEST(ForkliftForVehicle, AWiderPolygonScalesItsTrackByItsWidth) {
  vehicle::VehicleProfile reach = plant_forklift();
  reach.footprint = {{0.8, -0.45}, {0.8, 0.45}, {-0.6, 0.45}, {-0.8, 0.3}, {-0.8, -0.3}, {-0.6, -0.45}};
  reach.max_speed = 0.8;
  const auto c = ForkliftConfig::for_vehicle(reach);
  EXPECT_NEAR(c.sim.forklift.footprint.length, 1.6, 1e-12);
  EXPECT_NEAR(c.sim.forklift.footprint.width, 0.9, 1e-12);
  EXPECT_NEAR(c.sim.forklift.mecanum.half_track, 0.06 * 0.9 / 0.16, 1e-12);
  EXPECT_NEAR(sim::MecanumKinematics(c.sim.forklift.mecanum).limits().max_linear, 0.8, 1e-9);
}

TEST(ForkliftForVehicle, ARealForkliftCarriesAPalletAcrossThePlant) {
  // Built from the table's defaults, this forklift could not drive faster than 0.3 m/s while its
  // filter believed the commanded 1.2 m/s, and its 10 cm lookahead sat inside the estimate's
  // error: it turned on the spot on open road.
  const auto site =
      std::make_shared<const map::SiteMap>(map::load_site_map(fleet::test::source_path("/maps/plant.yaml")));
  ForkliftConfig c = ForkliftConfig::for_vehicle(plant_forklift());
  c.task.follower.v_max = 1.2;
  c.task.follower.omega_max = 1.0;
  const auto home = site->site.find_home("PF2")->pose;
  robot::Forklift f(c, site, home, 1, 1);
  std::map<int, geometry::Pose2> pallets;
  int id = 1;
  for (const auto& area : site->site.loading_areas) {
    if (area.pallet_at_start) pallets[id++] = area.pose;
  }
  f.set_standing_loads(pallets);
  const auto& from = site->site.find_area("FG5")->pose;
  const auto& to = site->site.find_area("EX7")->pose;
  ASSERT_TRUE(f.submit({"1", "FG5", from, "EX7", to}, nullptr));
  bool done = false;
  while (!done && f.status().time < 240.0) {
    f.step();
    for (const auto& e : f.take_events()) {
      ASSERT_NE(e.kind, RobotEvent::Kind::kFailed) << e.text;
      ASSERT_NE(e.kind, RobotEvent::Kind::kAreaEmpty) << e.text;
      if (e.kind == RobotEvent::Kind::kDone) {
        done = true;
        EXPECT_LT(geometry::distance(e.load_pose.position(), to.position()), 0.15);
      }
    }
  }
  EXPECT_TRUE(done) << "state " << f.status().task_state << " (" << f.status().detail << ") at " << f.status().truth.x
                    << ", " << f.status().truth.y;
}

TEST(ForkliftForVehicle, AForkliftLeavesItsStallBesideOneParkedInTheNext) {
  // Seen in the plant soak: fk3 stood 0.15 m off its stall's centre, yawed 3 degrees, with fk4
  // parked in the next stall. Its route starts with a short diagonal to the stall's road node;
  // swept along that diagonal its body's corner met fk4's, so it never left.
  PlantRobot plant;
  const auto& site = plant.site;
  auto& robot = plant.make("forklifts", {40.2455, 28.8761, -1.5152});
  const robot::Neighbour parked{"fk4", {41.5582, 29.0320, -1.5694}, {1.2, 0.8}, 0.0, 0.1};
  const geometry::Polygon parked_body = geometry::footprint_polygon(parked.pose, parked.footprint);
  const auto step = [&] { test::step_among(*robot, {parked}, {parked_body}); };
  while (robot->status().time < 1.0) step();
  ASSERT_TRUE(robot->submit({"38", "WA2", site->site.find_area("WA2")->pose, "EX4", site->site.find_area("EX4")->pose},
                            nullptr));
  double closest = std::numeric_limits<double>::infinity();
  while (robot->status().time < 11.0 && robot->status().truth.y > 27.5) {
    test::grant_everything(*robot);
    step();
    closest = std::min(closest,
                       geometry::convex_polygons_distance(
                           geometry::footprint_polygon(robot->status().truth, robot->status().footprint), parked_body));
  }
  EXPECT_LE(robot->status().truth.y, 27.5) << robot->status().task_state << " (" << robot->status().detail << ")";
  EXPECT_GE(closest, ForkliftConfig::for_vehicle(plant_forklift()).safety_gap);
}

TEST(ForkliftForVehicle, AForkliftLeavesItsStallForwardsFromWhereItStoppedComingHome) {
  // Seen in the plant soak: fk1 came home and stopped 6 cm short of its stall's road point, where
  // every route out starts. It turned round to touch that point and back again; beside fk2,
  // parked in the next stall, its corners met fk2's body half way round and it stood there,
  // facing the wall, until fk2 left.
  PlantRobot plant;
  const auto& site = plant.site;
  const geometry::Pose2 home = site->site.find_home("PF1")->pose;
  auto& robot = plant.make("forklifts", {home.x + 0.02, home.y - 0.07, home.yaw});
  const geometry::Pose2 next_home = site->site.find_home("PF2")->pose;
  const robot::Neighbour parked{"fk2", {next_home.x, next_home.y - 0.04, next_home.yaw}, {1.2, 0.8}, 0.0, 0.1};
  const geometry::Polygon parked_body = geometry::footprint_polygon(parked.pose, parked.footprint);
  const auto step = [&] { test::step_among(*robot, {parked}, {parked_body}); };
  while (robot->status().time < 1.0) step();
  ASSERT_TRUE(robot->submit({"19", "WA2", site->site.find_area("WA2")->pose, "EN1", site->site.find_area("EN1")->pose},
                            nullptr));
  double most_turned = 0.0;
  double closest = std::numeric_limits<double>::infinity();
  while (robot->status().time < 11.0 && robot->status().truth.y > 27.5) {
    test::grant_everything(*robot);
    step();
    most_turned = std::max(most_turned, std::abs(geometry::angle_diff(robot->status().truth.yaw, home.yaw)));
    closest = std::min(closest,
                       geometry::convex_polygons_distance(
                           geometry::footprint_polygon(robot->status().truth, robot->status().footprint), parked_body));
  }
  EXPECT_LE(robot->status().truth.y, 27.5) << robot->status().task_state << " (" << robot->status().detail << ")";
  EXPECT_LT(most_turned, 0.3);
  EXPECT_GE(closest, ForkliftConfig::for_vehicle(plant_forklift()).safety_gap);
}

TEST(ForkliftForVehicle, AReachTruckStoppedForAPickerOnItsWayNamesThePicker) {
  // Seen in the plant soak: a reach truck stops its stopping distance (0.5 m) short of a picker's
  // grown cells, about a metre from the picker's body; named from where it stood it reported
  // "an obstacle ahead", traffic never learnt whom it waited for, and the picker, waiting in turn
  // for the road the truck held, stood there with it for good.
  PlantRobot plant;
  const auto& site = plant.site;
  auto& robot = plant.make("reach_trucks", site->site.find_home("PR1")->pose);
  std::vector<robot::Neighbour> picker;
  const auto step = [&] {
    test::grant_everything(*robot);
    robot->navigation().set_neighbours(picker);
    robot->step();
  };
  while (robot->status().time < 1.0) step();
  ASSERT_TRUE(robot->submit({"7", "FG5", site->site.find_area("FG5")->pose, "RH4", site->site.find_area("RH4")->pose},
                            nullptr));
  while (robot->status().time < 20.0 && robot->navigation().follower().path().size() < 2) step();
  ASSERT_GE(robot->navigation().follower().path().size(), 2u);
  // Where the truck will be in 3 m: a picker stands there, reporting as it should.
  double left =
      3.0 + geometry::distance(robot->status().estimate.position(), robot->navigation().follower().path().front());
  geometry::Vec2 at = robot->navigation().follower().path().front();
  for (std::size_t i = 1; i < robot->navigation().follower().path().size() && left > 0.0; ++i) {
    const geometry::Vec2 a = robot->navigation().follower().path()[i - 1], b = robot->navigation().follower().path()[i];
    const double d = geometry::distance(a, b);
    at = d >= left ? a + (left / d) * (b - a) : b;
    left -= d;
  }
  picker = {{"pk9", {at.x, at.y, 0.0}, {0.65, 0.50}, 0.3, 0.1}};
  while (robot->status().time < 60.0 && !robot->status().detail.ends_with(" ahead")) step();
  EXPECT_EQ(robot->status().detail, "robot pk9 ahead");
  RecordProperty("gap", std::to_string(geometry::convex_polygons_distance(
                            geometry::footprint_polygon(robot->status().estimate, robot->status().footprint),
                            geometry::footprint_polygon(picker.front().pose, picker.front().footprint))));
  const double stopped_at = robot->status().time;
  while (robot->status().time < stopped_at + 3.5) step();
  EXPECT_EQ(robot->traffic_route().stopped_for, std::vector<std::string>{"pk9"}) << robot->status().detail;
}

TEST(ForkliftForVehicle, AForkliftComingHomeBetweenTwoParkedOnesBacksIntoItsStall) {
  // Seen in the plant soak: fk2 came home up its stall's spur facing the wall and turned round at
  // the end to the home heading, between fk1 and fk3 parked 1.2 m either side. Half way round its
  // corners came within the safety gap of theirs; it stood there, and fk1, sent out, waited for it.
  PlantRobot plant;
  const auto& site = plant.site;
  const geometry::Pose2 home = site->site.find_home("PF2")->pose;
  auto& robot = plant.make("forklifts", home);
  std::vector<robot::Neighbour> parked;
  std::vector<geometry::Polygon> parked_bodies;
  for (const auto& [robot_id, stall] : {std::pair{"fk1", "PF1"}, std::pair{"fk3", "PF3"}}) {
    parked.push_back({robot_id, site->site.find_home(stall)->pose, {1.2, 0.8}, 0.0, 0.1});
    parked_bodies.push_back(geometry::footprint_polygon(parked.back().pose, parked.back().footprint));
  }
  const auto step = [&] {
    test::grant_everything(*robot);
    test::step_among(*robot, parked, parked_bodies);
  };
  while (robot->status().time < 1.0) step();
  ASSERT_TRUE(robot->submit({"61", "PS2", site->site.find_area("PS2")->pose, "EX6", site->site.find_area("EX6")->pose},
                            nullptr));
  // Out of the stall and a few metres along the lane, then the order is taken away: home again.
  while (robot->status().time < 30.0 && geometry::distance(robot->status().truth.position(), home.position()) < 4.0)
    step();
  ASSERT_GE(geometry::distance(robot->status().truth.position(), home.position()), 4.0) << robot->status().detail;
  ASSERT_TRUE(robot->withdraw());
  bool home_reached = false;
  double most_turned_in_stall = 0.0;
  double closest = std::numeric_limits<double>::infinity();
  const double stall_mouth = home.y - 0.9;
  while (robot->status().time < 90.0 && !home_reached) {
    step();
    for (const auto& e : robot->take_events()) home_reached = home_reached || e.kind == RobotEvent::Kind::kHome;
    const geometry::Polygon body = geometry::footprint_polygon(robot->status().truth, robot->status().footprint);
    for (const auto& other : parked_bodies)
      closest = std::min(closest, geometry::convex_polygons_distance(body, other));
    if (robot->status().truth.y > stall_mouth) {
      most_turned_in_stall =
          std::max(most_turned_in_stall, std::abs(geometry::angle_diff(robot->status().truth.yaw, home.yaw)));
    }
  }
  EXPECT_TRUE(home_reached) << robot->status().task_state << " (" << robot->status().detail << ") at "
                            << robot->status().truth.x << ", " << robot->status().truth.y << ", yaw "
                            << robot->status().truth.yaw;
  EXPECT_LT(most_turned_in_stall, 0.3);
  EXPECT_GE(closest, ForkliftConfig::for_vehicle(plant_forklift()).safety_gap);
  EXPECT_LT(geometry::distance(robot->status().truth.position(), home.position()), 0.1);
}

TEST(ForkliftForVehicle, AReachTruckHandedARouteThatBacksUpAPlaceStopsWhereItsGrantEnds) {
  // Seen in the plant soak under the coordination core: a reach truck was handed a route that
  // went one place on, one back and on again, granted two places past the turns. Its path
  // follower ended the first leg a few centimetres short of the cusp, where the count of its
  // progress along the route had not yet passed it: that count stayed on the first leg, the room
  // left in the grant never shrank, and the truck drove its whole route, 20 m past its grant.
  PlantRobot plant;
  const auto& site = plant.site;
  auto& robot = plant.make("reach_trucks", site->site.find_home("PR1")->pose);
  const auto step = [&] {
    robot->navigation().set_neighbours({});
    robot->step();
  };
  while (robot->status().time < 1.0) {
    test::grant_everything(*robot);
    step();
  }
  ASSERT_TRUE(robot->submit({"7", "FG5", site->site.find_area("FG5")->pose, "RH4", site->site.find_area("RH4")->pose},
                            nullptr));
  // On the road and a few metres along its own route.
  while (robot->status().time < 40.0 && robot->traffic_route().progress < 4.0) {
    test::grant_everything(*robot);
    step();
  }
  const robot::TrafficRoute own = robot->traffic_route();
  ASSERT_GE(own.progress, 4.0) << robot->status().detail;
  const auto& points = site->graph.graph.points;
  const auto at = [&](int id) {
    return geometry::Vec2{points[static_cast<std::size_t>(id)].x, points[static_cast<std::size_t>(id)].y};
  };
  std::size_t behind = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < own.points.size(); ++k) {
    const double d =
        geometry::point_segment_distance(robot->status().estimate.position(), at(own.points[k]), at(own.points[k + 1]));
    if (d < best) {
      best = d;
      behind = k;
    }
  }
  ASSERT_LT(behind + 8, own.points.size());
  const auto p = [&](std::size_t k) { return own.points[behind + k]; };
  // On two points, back one, on again: granted first up to the cusp, then up to the third point
  // past where it stood.
  const std::vector<int> shuttle{p(0), p(1), p(2), p(1), p(2), p(3), p(4), p(5), p(6), p(7)};
  const auto metres_to = [&](int index) {
    double metres = 0.0;
    for (std::size_t k = 1; k <= static_cast<std::size_t>(index); ++k) {
      metres += geometry::distance(at(shuttle[k - 1]), at(shuttle[k]));
    }
    return metres;
  };
  robot::TrafficPermit handed{own.version + 1, 2, metres_to(2), {}, shuttle, false};
  robot->set_traffic_grant(handed);
  handed.route.clear();
  const double handed_at = robot->status().time;
  while (robot->status().time < handed_at + 20.0) {
    robot->set_traffic_grant(handed);
    step();
  }
  ASSERT_EQ(robot->traffic_route().version, handed.version);
  // Up to the cusp, close enough for traffic to count it there (within 5 cm), and no further.
  EXPECT_NEAR(robot->traffic_route().progress, handed.granted_distance, 0.03) << robot->status().detail;
  EXPECT_LT(geometry::distance(robot->status().truth.position(), at(p(2))), 0.1) << "its estimate's error aside";
  handed.granted_index = 5;
  handed.granted_distance = metres_to(5);
  const geometry::Vec2 grant_end = at(p(3));
  const geometry::Vec2 beyond = at(p(4));
  double farthest_past = -std::numeric_limits<double>::infinity();
  while (robot->status().time < handed_at + 60.0) {
    robot->set_traffic_grant(handed);
    step();
    // How far past the grant's end, along the way on.
    const double past = geometry::dot(robot->status().truth.position() - grant_end, beyond - grant_end) /
                        geometry::distance(beyond, grant_end);
    farthest_past = std::max(farthest_past, past);
  }
  EXPECT_EQ(robot->traffic_route().version, handed.version);
  EXPECT_NEAR(robot->traffic_route().progress, handed.granted_distance, 0.03) << robot->status().detail;
  EXPECT_LT(farthest_past, 0.05) << "drove past its grant: " << robot->status().detail;
}
