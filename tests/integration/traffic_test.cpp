// Traffic control with real processes: four agents sent across one another on table_a's
// single-lane roads all finish, with no footprint overlap in the simulation truth.

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <map>
#include <thread>

#include "cli/client.hpp"
#include "fleet_harness.hpp"
#include "monitor/collision_monitor.hpp"

using namespace fleet;
using namespace fleet::testing;
using namespace std::chrono_literals;

namespace {

/// One order per robot, each across the table: right to left, left to right, bottom to top,
/// top to bottom, all at once, so that the four routes meet in the middle and on the ring.
/// The ids of the orders placed; fewer than the robots when one was refused (a test failure).
std::vector<std::int64_t> send_crossing_orders(cli::FleetClient& client, const std::vector<std::string>& robots,
                                               const std::string& request_prefix) {
  const std::vector<std::pair<std::string, std::string>> trips{{"A3", "A8"}, {"A7", "A4"}, {"A1", "A6"}, {"A5", "A2"}};
  std::vector<std::int64_t> ids;
  for (std::size_t i = 0; i < trips.size() && i < robots.size(); ++i) {
    model::OrderRequest request;
    request.request_id = request_prefix + std::to_string(i);
    request.pick_area = trips[i].first;
    request.drop_area = trips[i].second;
    request.robot_id = robots[i];
    auto reply = client.request_order(request, 5000ms);
    // The harness sees every agent's state before the server may have: an order for a robot the
    // server has not heard from yet is refused as such, and is asked again.
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    for (int attempt = 1; reply && !reply->accepted && reply->error.find("has not been seen") != std::string::npos &&
                          std::chrono::steady_clock::now() < deadline;
         ++attempt) {
      std::this_thread::sleep_for(200ms);
      request.request_id = request_prefix + std::to_string(i) + "-" + std::to_string(attempt);
      reply = client.request_order(request, 5000ms);
    }
    EXPECT_TRUE(reply && reply->accepted) << (reply ? reply->error : "no reply");
    if (!reply || !reply->accepted) break;
    ids.push_back(reply->order_id);
  }
  return ids;
}

/// Agents `robots` (up to four) sent across one another (send_crossing_orders) under traffic
/// control with `extra` settings for every process: every order ends DONE, no footprints overlap.
void cross_the_table(int domain, const std::vector<std::string>& robots, const std::vector<std::string>& extra,
                     const std::string& core_log) {
  FleetHarness fleet(domain, 10.0);
  fleet.start_server(extra);
  for (const auto& r : robots) fleet.start_agent(r, extra);
  ASSERT_TRUE(fleet.wait_for_robots(robots));

  // The agents publish before the server is up on a loaded host: its log is read once it answers.
  cli::FleetClient client(static_cast<std::uint32_t>(fleet.domain()));
  ASSERT_TRUE(client.find_server(5000ms));
  EXPECT_NE(fleet.log_of("fleet-server").find(core_log), std::string::npos);
  dds::Reader<model::SimTruth> truths(client.participant(), dds::qos::live_state(), dds::robot_report_partitions());
  const std::vector<std::int64_t> ids = send_crossing_orders(client, robots, "traffic-test-");
  ASSERT_EQ(ids.size(), robots.size());

  monitor::CollisionMonitor collisions;
  std::map<std::int64_t, std::string> final_state;
  const auto deadline = std::chrono::steady_clock::now() + 150s;
  while (final_state.size() < ids.size() && std::chrono::steady_clock::now() < deadline) {
    truths.take_data([&](model::SimTruth&& t) { collisions.update(t.robot_id, t.pose, t.footprint, t.sim_time); });
    for (const auto& info : client.take_order_updates()) {
      if (info.state == "DONE" || info.state == "FAILED" || info.state == "CANCELLED") {
        final_state[info.order_id] = info.state + (info.reason.empty() ? "" : ": " + info.reason);
      }
    }
    std::this_thread::sleep_for(10ms);
  }
  for (std::int64_t id : ids) {
    ASSERT_TRUE(final_state.contains(id)) << "order " << id << " did not end within 150 s (1500 s sim); server log:\n"
                                          << fleet.log_of("fleet-server");
    EXPECT_EQ(final_state[id], "DONE") << "order " << id;
  }
  EXPECT_TRUE(collisions.collisions().empty())
      << collisions.collisions().size() << " collisions, the first between " << collisions.collisions().front().robot_a
      << " and " << collisions.collisions().front().robot_b;
}

}  // namespace

TEST(Traffic, FourRobotsSentAcrossOneAnotherAllFinishWithoutCollision) {
  cross_the_table(74, {"fl1", "fl2", "fl3", "fl4"}, {}, "traffic control on:");
}

// The coordination core in the server (traffic.core places): requests, grants and the driving
// they allow cross the wire; two robots on their way across the table (four head-on meet in
// knots the live core does not untangle yet: docs/known-limits.md).
TEST(Traffic, UnderTheCoordinationCoreRobotsCrossTheTable) {
  cross_the_table(79, {"fl1", "fl3"}, {"--set", "traffic.core=places"}, "traffic control on (coordination core)");
}

// Regression: a robot paused while it waited for traffic and resumed after the road was granted
// to it stood in WAITING for good, and the robots behind it waited on that grant.
TEST(Traffic, ARobotPausedWhileItWaitsForTrafficDrivesOnWhenResumedAndEveryOrderFinishes) {
  FleetHarness fleet(89, 10.0);
  fleet.start_server();
  const std::vector<std::string> robots{"fl1", "fl2", "fl3", "fl4"};
  for (const auto& r : robots) fleet.start_agent(r);
  ASSERT_TRUE(fleet.wait_for_robots(robots));
  cli::FleetClient client(static_cast<std::uint32_t>(fleet.domain()));
  ASSERT_TRUE(client.find_server(5000ms));
  dds::Reader<model::RobotState> states(client.participant(), dds::qos::live_state(), dds::robot_report_partitions());
  const std::vector<std::int64_t> ids = send_crossing_orders(client, robots, "pause-test-");
  ASSERT_EQ(ids.size(), robots.size());

  auto control = [&](const std::string& verb, const std::string& robot) {
    model::Command command;
    command.request_id = "pause-test-" + verb + "-" + robot;
    command.verb = verb;
    command.target = robot;
    const auto reply = client.send_command(command, 5000ms);
    return reply && reply->accepted;
  };
  // The first robot seen waiting for traffic is paused for 60 s sim, long enough for the road
  // it waits for to be granted meanwhile, then resumed.
  std::string paused;
  std::map<std::int64_t, std::string> final_state;
  auto paused_at = std::chrono::steady_clock::now();
  bool resumed = false;
  const auto deadline = std::chrono::steady_clock::now() + 170s;
  while (final_state.size() < ids.size() && std::chrono::steady_clock::now() < deadline) {
    states.take_data([&](model::RobotState&& state) {
      if (paused.empty() && state.task_state == "WAITING" && state.order_id != 0) {
        ASSERT_TRUE(control("pause", state.robot_id));
        paused = state.robot_id;
        paused_at = std::chrono::steady_clock::now();
      }
    });
    if (!paused.empty() && !resumed && std::chrono::steady_clock::now() - paused_at > 6s) {
      ASSERT_TRUE(control("resume", paused));
      resumed = true;
    }
    for (const auto& info : client.take_order_updates()) {
      if (info.state == "DONE" || info.state == "FAILED" || info.state == "CANCELLED") {
        final_state[info.order_id] = info.state + (info.reason.empty() ? "" : ": " + info.reason);
      }
    }
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_FALSE(paused.empty()) << "no robot waited for traffic; server log:\n" << fleet.log_of("fleet-server");
  EXPECT_TRUE(resumed);
  for (std::int64_t id : ids) {
    ASSERT_TRUE(final_state.contains(id)) << "order " << id << " did not end within 170 s (1700 s sim); " << paused
                                          << " was paused while waiting; its log:\n"
                                          << fleet.log_of("fleet-agent-" + paused);
    EXPECT_EQ(final_state[id], "DONE") << "order " << id;
  }
}

TEST(MapSwitch, EveryAgentGetsTheNewMapReplansOnItAndFinishesItsOrder) {
  FleetHarness fleet(76, 10.0);
  fleet.start_server();
  const std::vector<std::string> robots{"fl1", "fl2"};
  for (const auto& r : robots) fleet.start_agent(r);
  ASSERT_TRUE(fleet.wait_for_robots(robots));

  const auto maps = fleet.fleetctl({"--json", "map", "list"}, 30);
  ASSERT_EQ(maps.exit_code, 0) << maps.err;
  EXPECT_NE(maps.out.find("table_a_north_closed"), std::string::npos) << maps.out;

  cli::FleetClient client(static_cast<std::uint32_t>(fleet.domain()));
  ASSERT_TRUE(client.find_server(5000ms));
  model::OrderRequest request;
  request.request_id = "map-switch-test";
  request.pick_area = "A5";  // top right to bottom left: across the middle, where a road closes
  request.drop_area = "A8";
  request.robot_id = "fl2";
  const auto reply = client.request_order(request, 5000ms);
  ASSERT_TRUE(reply && reply->accepted) << (reply ? reply->error : "no reply");

  // Bad requests: an unknown map is bad input; one robot alone is refused under traffic control.
  const auto unknown = fleet.fleetctl({"map", "set", "table_b"}, 30);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("'table_b'"), std::string::npos) << unknown.err;
  const auto alone = fleet.fleetctl({"map", "set", "table_a_north_closed", "--robot", "fl1"}, 30);
  EXPECT_EQ(alone.exit_code, 1);
  EXPECT_NE(alone.err.find("traffic control"), std::string::npos) << alone.err;

  const auto set = fleet.fleetctl({"map", "set", "table_a_north_closed"}, 30);
  ASSERT_EQ(set.exit_code, 0) << set.err;
  // Every robot reports the new map, and the order still ends DONE, planned on the new roads.
  bool switched = false;
  for (int i = 0; i < 100 && !switched; ++i) {
    const auto states = client.robot_states(100ms);
    switched = states.size() == robots.size();
    for (const auto& [id, s] : states) switched = switched && s.map_id == "table_a_north_closed";
  }
  EXPECT_TRUE(switched);
  // Each agent reports how late its control steps run against the clock (at most a second
  // behind: later it jumps the clock and counts the steps it skipped).
  for (const auto& [id, s] : client.robot_states(300ms)) {
    EXPECT_NEAR(s.control_period, 1.0 / 70.0, 1e-9) << id;
    EXPECT_GE(s.control_lag_p99, s.control_lag_p50) << id;
    EXPECT_LE(s.control_lag_p99, 1.0) << id;
    EXPECT_GE(s.control_steps_skipped, 0) << id;
  }
  for (const auto& r : robots) {
    EXPECT_NE(fleet.log_of("fleet-agent-" + r).find("map switched from 'table_a' to 'table_a_north_closed'"),
              std::string::npos)
        << r;
  }
  const auto done = client.follow_order(
      reply->order_id, [](const model::OrderInfo&) {}, 150s);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->state, "DONE") << done->reason;
  // Requests sent on the old map before an agent heard of the switch are set aside, never taken
  // as routes on the new graph (whose point numbers mean other places).
  EXPECT_EQ(fleet.log_of("fleet-server").find(" refused ("), std::string::npos) << fleet.log_of("fleet-server");
}
