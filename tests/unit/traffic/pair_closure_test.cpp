// A loader's pair in a one-way rack lane of the plant (set_partners): the lane behind the
// transporter is closed to third robots, so none comes between it and its picker.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "test_grants.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::traffic {
namespace {

using testing::grant_of;

constexpr double kStep = 0.05, kSpeed = 1.0;  // s, m/s

struct PlantLane {
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/sites/plant.yaml"));
  map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/plant.yaml"));
  TrafficManager m{site.graph.graph, configuration_from(config)};
  int stacker = vehicle_type_of(config, "stackers");
  int picker = vehicle_type_of(config, "pickers");
  int forklift = vehicle_type_of(config, "forklifts");

  /// A route along the rack aisle lane at `y` from x = `from` to x = `to`, on `type`'s lanes.
  std::vector<int> along(int type, double y, double from, double to) {
    const auto& lanes = m.route_graph(type);
    return m.search(type).shortest(map::nearest_point(lanes, from, y), map::nearest_point(lanes, to, y));
  }

  /// Robot 1 drives `route` alone for 30 s from t = 0, at kSpeed within its grants; `t` ends
  /// after that. How far it got.
  double drive_alone(const std::vector<int>& route, double& t) {
    EXPECT_EQ(m.submit_route({1, 1, route}, 0.0), SubmitStatus::kAccepted);
    double d1 = 0.0;
    for (int i = 0; i < 20 * 30; ++i, t += kStep) {
      const auto r = m.update(t);
      if (const Grant* g = grant_of(r, 1)) d1 = std::max(d1, std::min(g->granted_distance, d1 + kSpeed * kStep));
      m.report_progress({1, 1, d1, {}}, t);
    }
    return d1;
  }
};

// The south lane of the aisle between R1 and R2 runs east. The transporter (1) drives in and
// stands at x = 45; a forklift (3) coming along the lane from the aisle's west end is kept out of
// the aisle, waits for the transporter and is routed round within seconds; the picker (2) drives
// in behind the transporter.
TEST(PairClosure, AThirdRobotIsKeptOutOfTheLaneBehindATransporterAndGoesRound) {
  PlantLane plant;
  TrafficManager& m = plant.m;
  m.set_robot_type(1, plant.stacker);
  m.set_robot_type(2, plant.picker);
  m.set_robot_type(3, plant.forklift);
  m.set_partners({{1, 2}});
  constexpr double kLane = 10.945;
  const auto transporter = plant.along(plant.stacker, kLane, 38.0, 45.0);
  ASSERT_GT(transporter.size(), 5u) << "the lane runs east";
  double t = 0.0;
  const double d1 = plant.drive_alone(transporter, t);
  ASSERT_GT(d1, 6.5) << "the transporter stands at the end of its route";

  // From the cross aisle west of the racks, through the lane, to the cross aisle east of them.
  const auto& lanes = m.route_graph(plant.forklift);
  const auto through =
      m.search(plant.forklift).shortest(map::nearest_point(lanes, 29.1, 14.0), map::nearest_point(lanes, 58.0, 14.0));
  ASSERT_GT(through.size(), 10u);
  ASSERT_TRUE(std::any_of(through.begin(), through.end(), [&](int point) {
    const auto& q = lanes.points[static_cast<std::size_t>(point)];
    return std::abs(q.y - kLane) < 0.3 && q.x > 40.0 && q.x < 44.0;
  })) << "its shortest way leads through the lane";
  ASSERT_EQ(m.submit_route({3, 1, through}, t), SubmitStatus::kAccepted);
  const auto in_behind = plant.along(plant.picker, kLane, 33.0, 42.5);
  ASSERT_GT(in_behind.size(), 5u);
  ASSERT_EQ(m.submit_route({2, 1, in_behind}, t), SubmitStatus::kAccepted);
  double d2 = 0.0, d3 = 0.0;
  bool kept_out = false, rerouted = false;
  double waited = 0.0;
  for (int i = 0; i < 20 * 60; ++i, t += kStep) {
    const auto r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    if (const Grant* g = grant_of(r, 2)) d2 = std::max(d2, std::min(g->granted_distance, d2 + kSpeed * kStep));
    m.report_progress({2, 1, d2, {}}, t);
    m.report_progress({1, 1, d1, {}}, t);
    if (const Grant* g = grant_of(r, 3); g != nullptr && !rerouted) {
      if (g->instruction == Instruction::kReroute) {
        rerouted = true;
        // The way round stays out of the aisle's south lane west of the transporter.
        for (int point : g->route) {
          const auto& q = m.route_graph(plant.forklift).points[static_cast<std::size_t>(point)];
          EXPECT_FALSE(std::abs(q.y - kLane) < 0.3 && q.x > 33.5 && q.x < 44.0) << q.x << ", " << q.y;
        }
        continue;
      }
      d3 = std::max(d3, std::min(g->granted_distance, d3 + kSpeed * kStep));
      if (g->status == GrantStatus::kWaiting && g->blocked_by == std::vector<int>{1}) {
        kept_out = true;
        waited = g->waited_s;
      }
    }
    if (!rerouted) m.report_progress({3, 1, d3, {}}, t);
  }
  EXPECT_TRUE(kept_out) << "the forklift never waited for the transporter";
  EXPECT_TRUE(rerouted) << "the forklift was not routed round";
  EXPECT_LT(waited, 10.0);
  EXPECT_GT(d2, 7.0) << "the picker drives in behind its transporter";
}

// Without the pair, the same forklift drives into the lane and queues behind the standing stacker.
TEST(PairClosure, WithoutPartnersTheLaneStaysOpen) {
  PlantLane plant;
  TrafficManager& m = plant.m;
  m.set_robot_type(1, plant.stacker);
  m.set_robot_type(3, plant.forklift);
  constexpr double kLane = 10.945;
  const auto transporter = plant.along(plant.stacker, kLane, 38.0, 45.0);
  double t = 0.0, d3 = 0.0;
  const double d1 = plant.drive_alone(transporter, t);
  const auto& lanes = m.route_graph(plant.forklift);
  const auto through =
      m.search(plant.forklift).shortest(map::nearest_point(lanes, 29.1, 14.0), map::nearest_point(lanes, 58.0, 14.0));
  ASSERT_EQ(m.submit_route({3, 1, through}, t), SubmitStatus::kAccepted);
  for (int i = 0; i < 20 * 30; ++i, t += kStep) {
    const auto r = m.update(t);
    if (const Grant* g = grant_of(r, 3)) d3 = std::max(d3, std::min(g->granted_distance, d3 + kSpeed * kStep));
    m.report_progress({3, 1, d3, {}}, t);
    m.report_progress({1, 1, d1, {}}, t);
  }
  double entered_x = 0.0;
  for (std::size_t k = 0; k < through.size(); ++k) {
    const auto& q = m.route_graph(plant.forklift).points[static_cast<std::size_t>(through[k])];
    if (std::abs(q.y - kLane) < 0.3 && q.x > 34.0) {
      entered_x = q.x;
      break;
    }
  }
  EXPECT_GT(entered_x, 0.0);
  EXPECT_GT(d3, 3.0) << "it drives on into the aisle";
}

// The road between R2 and R3 has two lanes that meet only where they fan out at its ends. A
// transporter stands at a stand in the westbound lane (x = 48.25); a stacker on the eastbound lane
// from the packaging road passes it on its way round to the aisle south of R2: the two lanes are
// taken in turn only at their ends, not along the whole road.
TEST(PairClosure, ARobotOnTheOppositeLanePassesATransporterStandingInItsLane) {
  PlantLane plant;
  TrafficManager& m = plant.m;
  m.set_robot_type(1, plant.stacker);
  m.set_robot_type(2, plant.picker);
  m.set_robot_type(3, plant.stacker);
  m.set_partners({{1, 2}});
  const auto& lanes = m.route_graph(plant.stacker);
  const auto transporter =
      m.search(plant.stacker).shortest(map::nearest_point(lanes, 57.0, 17.85), map::nearest_point(lanes, 48.3, 17.85));
  ASSERT_GT(transporter.size(), 10u);
  double t = 0.0, d3 = 0.0;
  const double d1 = plant.drive_alone(transporter, t);
  ASSERT_GT(d1, 8.5) << "the transporter stands at the end of its route";
  // Two stretches of the eastbound lane meet the westbound one: its two ends.
  const auto& zones = m.zones();
  const int east = zones.place_of(map::nearest_point(lanes, 45.25, 16.35));
  const int west = zones.place_of(map::nearest_point(lanes, 45.25, 17.85));
  EXPECT_EQ(zones.opposite_lanes(plant.stacker, zones.corridor(east), plant.stacker).size(), 2u);
  EXPECT_FALSE(zones.conflict(plant.stacker, east, plant.stacker, west));

  const auto round =
      m.search(plant.stacker).shortest(map::nearest_point(lanes, 25.75, 16.35), map::nearest_point(lanes, 47.0, 12.45));
  ASSERT_EQ(m.submit_route({3, 1, round}, t), SubmitStatus::kAccepted);
  for (int i = 0; i < 20 * 90; ++i, t += kStep) {
    const auto r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    if (const Grant* g = grant_of(r, 3)) d3 = std::max(d3, std::min(g->granted_distance, d3 + kSpeed * kStep));
    m.report_progress({3, 1, d3, {}}, t);
    m.report_progress({1, 1, d1, {}}, t);
  }
  EXPECT_GT(d3, 40.0) << "the stacker waited for the transporter standing in the other lane";
}

// Two pairs stand in the westbound lanes north and south of R2, each transporter with the lane
// behind it closed. A reach truck coming up the east loop, bound west through the southern lane,
// is kept out of it and goes round: not through the other closed lane (where it would stand, kept
// out again, on the way of that pair's picker) but along the north road.
TEST(PairClosure, ARobotKeptOutOfAClosedLaneGoesRoundEveryClosedLane) {
  PlantLane plant;
  TrafficManager& m = plant.m;
  const int reach = vehicle_type_of(plant.config, "reach_trucks");
  for (int transporter : {1, 4}) m.set_robot_type(transporter, plant.stacker);
  for (int loader : {2, 5}) m.set_robot_type(loader, plant.picker);
  m.set_robot_type(3, reach);
  m.set_partners({{1, 2}, {4, 5}});
  constexpr double kSouth = 12.45, kNorth = 17.85;  // the westbound lanes south and north of R2
  const auto& lanes = m.route_graph(plant.stacker);
  const auto north = m.search(plant.stacker)
                         .shortest(map::nearest_point(lanes, 57.0, kNorth), map::nearest_point(lanes, 39.8, kNorth));
  const auto south =
      m.search(plant.stacker).shortest(map::nearest_point(lanes, 58.0, 8.5), map::nearest_point(lanes, 43.3, kSouth));
  ASSERT_EQ(m.submit_route({4, 1, north}, 0.0), SubmitStatus::kAccepted);
  ASSERT_EQ(m.submit_route({1, 1, south}, 0.0), SubmitStatus::kAccepted);
  double t = 0.0, d1 = 0.0, d4 = 0.0, d3 = 0.0;
  const auto drive = [&](int id, double& d, const UpdateResult& r) {
    if (const Grant* g = grant_of(r, id)) d = std::max(d, std::min(g->granted_distance, d + kSpeed * kStep));
    m.report_progress({id, 1, d, {}}, t);
  };
  for (int i = 0; i < 20 * 30; ++i, t += kStep) {
    const auto r = m.update(t);
    drive(1, d1, r);
    drive(4, d4, r);
  }
  ASSERT_GT(d1, 17.0) << "the southern transporter stands at the end of its route";
  ASSERT_GT(d4, 17.0) << "the northern transporter stands at the end of its route";
  const auto& truck_lanes = m.route_graph(reach);
  const auto west = m.search(reach).shortest(map::nearest_point(truck_lanes, 50.0, 6.12),
                                             map::nearest_point(truck_lanes, 20.0, 16.36));
  ASSERT_TRUE(std::any_of(west.begin(), west.end(), [&](int point) {
    const auto& q = truck_lanes.points[static_cast<std::size_t>(point)];
    return std::abs(q.y - kSouth) < 0.3 && q.x < 43.0;
  })) << "its shortest way leads through the southern lane";
  ASSERT_EQ(m.submit_route({3, 1, west}, t), SubmitStatus::kAccepted);
  bool kept_out = false;
  std::vector<int> round;
  for (int i = 0; i < 20 * 60 && round.empty(); ++i, t += kStep) {
    const auto r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    drive(1, d1, r);
    drive(4, d4, r);
    const Grant* g = grant_of(r, 3);
    ASSERT_NE(g, nullptr);
    if (g->instruction == Instruction::kReroute) {
      round = g->route;
      break;
    }
    kept_out = kept_out || (g->status == GrantStatus::kWaiting && g->blocked_by == std::vector<int>{1});
    drive(3, d3, r);
  }
  EXPECT_TRUE(kept_out) << "the truck never waited for the southern transporter";
  ASSERT_FALSE(round.empty()) << "the truck was not routed round";
  for (int point : round) {
    const auto& q = truck_lanes.points[static_cast<std::size_t>(point)];
    EXPECT_FALSE(std::abs(q.y - kSouth) < 0.3 && q.x > 33.5 && q.x < 56.0) << "south lane " << q.x << ", " << q.y;
    EXPECT_FALSE(std::abs(q.y - kNorth) < 0.3 && q.x > 33.5 && q.x < 56.0) << "north lane " << q.x << ", " << q.y;
  }
}

// A reach truck bound for a place in the lane behind a standing transporter cannot go round:
// its goal lies in the closed stretch. It waited at the lane's mouth, on the east loop where the
// transporter's picker, queued behind it, comes by to its stop, and the three stood for good. It
// waits on a siding off the pair's ways instead, and the picker reaches its stop.
TEST(PairClosure, ARobotBoundIntoAClosedLaneWaitsOffThePickersWay) {
  PlantLane plant;
  TrafficManager& m = plant.m;
  const int reach = vehicle_type_of(plant.config, "reach_trucks");
  m.set_robot_type(1, plant.stacker);
  m.set_robot_type(2, plant.picker);
  m.set_robot_type(3, reach);
  m.set_partners({{1, 2}});
  constexpr double kLane = 12.45;  // the westbound lane south of R2
  const auto& lanes = m.route_graph(plant.stacker);
  const auto transporter =
      m.search(plant.stacker).shortest(map::nearest_point(lanes, 58.0, 8.5), map::nearest_point(lanes, 43.3, kLane));
  double t = 0.0;
  const double d1 = plant.drive_alone(transporter, t);
  ASSERT_GT(d1, 17.0) << "the transporter stands at the end of its route";
  const auto& truck_lanes = m.route_graph(reach);
  const auto into = m.search(reach).shortest(map::nearest_point(truck_lanes, 53.0, 6.12),
                                             map::nearest_point(truck_lanes, 50.0, kLane));
  const auto& picker_lanes = m.route_graph(plant.picker);
  const auto to_stop =
      m.search(plant.picker)
          .shortest(map::nearest_point(picker_lanes, 47.0, 6.12), map::nearest_point(picker_lanes, 45.5, kLane));
  ASSERT_GT(into.size(), 10u);
  ASSERT_GT(to_stop.size(), 10u);
  ASSERT_EQ(m.submit_route({3, 1, into}, t), SubmitStatus::kAccepted);
  ASSERT_EQ(m.submit_route({2, 1, to_stop}, t), SubmitStatus::kAccepted);
  std::uint64_t v3 = 1;
  double d2 = 0.0, d3 = 0.0;
  bool sided = false;
  for (int i = 0; i < 20 * 120; ++i, t += kStep) {
    const auto r = m.update(t);
    ASSERT_EQ(m.check_invariant(), "");
    if (const Grant* g = grant_of(r, 2)) d2 = std::max(d2, std::min(g->granted_distance, d2 + kSpeed * kStep));
    if (const Grant* g = grant_of(r, 3)) {
      if (g->instruction != Instruction::kNone && g->version != v3) {
        if (g->instruction == Instruction::kSiding) {
          sided = true;
          for (int point : g->route) {
            const auto& q = truck_lanes.points[static_cast<std::size_t>(point)];
            EXPECT_FALSE(std::abs(q.y - kLane) < 0.3 && q.x > 43.3 && q.x < 56.0) << q.x << ", " << q.y;
          }
        }
        v3 = g->version;
        d3 = 0.0;
      } else {
        d3 = std::max(d3, std::min(g->granted_distance, d3 + kSpeed * kStep));
      }
    }
    m.report_progress({1, 1, d1, {}}, t);
    m.report_progress({2, 1, d2, {}}, t);
    m.report_progress({3, v3, d3, {}}, t);
  }
  EXPECT_TRUE(sided) << "the truck was not sent off the picker's way";
  double length = 0.0;
  for (std::size_t k = 1; k < to_stop.size(); ++k) {
    const auto& a = picker_lanes.points[static_cast<std::size_t>(to_stop[k - 1])];
    const auto& b = picker_lanes.points[static_cast<std::size_t>(to_stop[k])];
    length += std::hypot(b.x - a.x, b.y - a.y);
  }
  EXPECT_GT(d2, length - 0.5) << "the picker did not reach its stop behind its transporter";
}

}  // namespace
}  // namespace fleet::traffic
