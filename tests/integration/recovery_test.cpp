// Faults that real fleets meet, with real processes: a server killed with SIGKILL and restarted
// (with a robot it has not heard from yet),
// an agent killed mid-order, an agent that starts after obstacles were switched on, a search that
// misses a pallet the server put down, a robot lost while it searches at the pick area.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <thread>

#include "cli/client.hpp"
#include "dds/qos.hpp"
#include "fleet_harness.hpp"
#include "orders/order.hpp"
#include "scripted_fleet.hpp"

using namespace fleet;
using namespace fleet::testing;
using namespace std::chrono_literals;

// A robot that puts its pallet down while the server is down (killed as the robot drops) reports
// DONE to no one; its report is latched, so the restarted server hears it and ends the order.
TEST(Recovery, AnOrderFinishedWhileTheServerWasDownIsDoneAfterTheRestart) {
  ScriptedFleet s(91);
  const auto assignment = s.start_with_order();
  ASSERT_TRUE(assignment.has_value()) << s.server_log();
  const std::int64_t id = assignment->order_id;
  s.robot.state.order_id = id;
  s.robot.state.task_state = "TRACK_PATH";
  s.robot.report(*assignment, "ACCEPTED");
  for (const char* phase : {"TO_PICK", "SEARCHING", "PICKING"}) s.robot.report(*assignment, phase);
  s.robot.state.carrying_pallet = true;
  s.robot.report(*assignment, "TO_DROP");
  s.robot.report(*assignment, "DROPPING");
  ASSERT_TRUE(s.order_reaches(id, "DROPPING")) << s.server_log();

  s.fleet.processes().signal(0, SIGKILL);
  std::this_thread::sleep_for(300ms);
  s.fleet.processes().reap();
  s.robot.state.carrying_pallet = false;
  s.robot.state.task_state = "GO_HOME";
  s.robot.report(*assignment, "DONE");
  std::this_thread::sleep_for(500ms);
  s.fleet.processes().restart(0);
  ASSERT_TRUE(s.client.find_server(5s));
  EXPECT_TRUE(s.robot.keeps_answering_until([&] { return order_in_state(s.client, id, "DONE"); }, 10s))
      << s.server_log();
}

// The same with a real agent: the server is killed as the robot starts to put the pallet down,
// and comes back after the robot has finished.
TEST(Recovery, ServerKilledAsTheRobotDropsHearsTheOrderDoneWhenBack) {
  FleetHarness fleet(92, 10.0);
  fleet.start_server({"--verbose"});
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));
  cli::FleetClient client(92);
  ASSERT_TRUE(client.find_server(5s));
  const auto reply = order_a1_to_a2(client);
  ASSERT_TRUE(reply && reply->accepted);
  ASSERT_TRUE(reaches_phase(client, reply->order_id, "DROPPING", "fl1", 60s)) << fleet.log_of("fleet-server");
  fleet.processes().signal(0, SIGKILL);
  std::this_thread::sleep_for(1700ms);
  fleet.processes().reap();
  fleet.processes().restart(0);
  ASSERT_TRUE(client.find_server(5s));
  EXPECT_TRUE(eventually([&] { return order_in_state(client, reply->order_id, "DONE"); }, 15s))
      << fleet.log_of("fleet-server") << fleet.log_of("fleet-agent-fl1");
}

TEST(Recovery, ServerKilledMidRunAndRestartedLosesNoOrderAndRunsNoneTwice) {
  FleetHarness fleet(70, 10.0);
  fleet.start_server({"--auto-orders"});
  const std::vector<std::string> robots{"fl1", "fl2"};
  for (const auto& r : robots) fleet.start_agent(r);
  std::this_thread::sleep_for(6s);
  fleet.processes().signal(0, SIGKILL);  // the server, mid-run
  std::this_thread::sleep_for(1500ms);
  fleet.processes().reap();
  fleet.processes().restart(0);

  // The robots carry on under the restarted server: wait (at most 60 s) for two orders done.
  cli::FleetClient client(70);
  ASSERT_TRUE(client.find_server(5s));
  const auto orders = orders_once_done(client, 2, 60s);
  ASSERT_FALSE(orders.empty());
  // Ids are contiguous from 1: none vanished.
  EXPECT_EQ(orders.begin()->first, 1);
  EXPECT_EQ(static_cast<std::size_t>(orders.rbegin()->first), orders.size());
  long done = 0;
  for (const auto& [id, info] : orders) {
    ASSERT_TRUE(orders::parse_status(info.state).has_value()) << id << " " << info.state;
    done += info.state == "DONE";
    int done_events = 0;
    for (const auto& e : info.history) done_events += e.state == "DONE";
    EXPECT_LE(done_events, 1) << "order " << id;
  }
  EXPECT_GE(done, 2);
  // No order was carried out twice, by one robot or by two.
  for (const auto& [id, count] : done_counts(fleet, robots)) EXPECT_EQ(count, 1) << "order " << id << " done twice";
  EXPECT_NE(fleet.log_of("fleet-server").find("restored"), std::string::npos);
}

TEST(Recovery, AgentKilledWithoutPalletHasItsOrderRequeuedAndDoneByAnother) {
  FleetHarness fleet(71, 2.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));  // fl1 alone is free: it takes the order
  fleet.start_agent("fl2");
  cli::FleetClient client(71);
  ASSERT_TRUE(client.find_server(5s));
  const auto reply = order_a1_to_a2(client);
  ASSERT_TRUE(reply && reply->accepted) << (reply ? reply->error : "no reply");
  const std::int64_t id = reply->order_id;

  ASSERT_TRUE(reaches_phase(client, id, "TO_PICK", "fl1", 10s));
  fleet.processes().signal(1, SIGKILL);  // fl1, on its way to the pallet

  const auto final_info = client.follow_order(
      id, [](const model::OrderInfo&) {}, 150s);
  ASSERT_TRUE(final_info.has_value()) << fleet.log_of("fleet-server") << fleet.log_of("fleet-agent-fl2");
  EXPECT_EQ(final_info->state, "DONE");
  EXPECT_EQ(final_info->robot_id, "fl2");
  bool requeued = false;
  for (const auto& e : final_info->history)
    requeued = requeued || (e.state == "QUEUED" && e.reason.find("fl1 lost") != std::string::npos);
  EXPECT_TRUE(requeued) << fleet.log_of("fleet-server");
}

TEST(Recovery, AgentKilledWithThePalletComesBackEmptyAndThePalletGoesBackToItsArea) {
  FleetHarness fleet(78, 2.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));
  cli::FleetClient client(78);
  ASSERT_TRUE(client.find_server(5s));
  const auto reply = order_a1_to_a2(client);
  ASSERT_TRUE(reply && reply->accepted) << (reply ? reply->error : "no reply");
  const std::int64_t id = reply->order_id;
  ASSERT_TRUE(reaches_phase(client, id, "TO_DROP", "", 60s)) << fleet.log_of("fleet-agent-fl1");
  int pallet = -1;
  for (const auto& [pallet_id, p] : client.pallets(300ms)) {
    if (p.carried_by == "fl1") pallet = pallet_id;
  }
  ASSERT_GE(pallet, 0) << "no pallet on fl1's forks";
  // Killed with the pallet and restarted at its home with empty forks (its software forgot the
  // order): the order fails with the reason, and the pallet is put back where it was picked.
  fleet.processes().signal(1, SIGKILL);
  std::this_thread::sleep_for(1500ms);
  fleet.processes().restart(1);
  const auto final_info = client.follow_order(
      id, [](const model::OrderInfo&) {}, 60s);
  ASSERT_TRUE(final_info.has_value()) << fleet.log_of("fleet-server");
  EXPECT_EQ(final_info->state, "FAILED");
  EXPECT_NE(final_info->reason.find("without the order's pallet"), std::string::npos) << final_info->reason;
  ASSERT_TRUE(eventually(
      [&] {
        const auto pallets = client.pallets(100ms);
        auto it = pallets.find(pallet);
        return it != pallets.end() && it->second.carried_by.empty() && it->second.area_id == "A1";
      },
      10s))
      << fleet.log_of("fleet-server");
  // The pallet is in circulation again: a robot sent to A1 lifts it.
  const auto again = order_a1_to_a2(client);
  ASSERT_TRUE(again && again->accepted) << (again ? again->error : "no reply");
  EXPECT_TRUE(reaches_phase(client, again->order_id, "TO_DROP", "", 90s)) << fleet.log_of("fleet-server");
  bool lifted = false;
  for (const auto& [pallet_id, p] : client.pallets(300ms))
    lifted = lifted || (pallet_id == pallet && p.carried_by == "fl1");
  EXPECT_TRUE(lifted) << "pallet " << pallet << " is not on fl1's forks";
}

TEST(Recovery, AgentStartingAfterObstaclesWereEnabledSeesThem) {
  FleetHarness fleet(72, 10.0);
  fleet.start_server();
  cli::FleetClient client(72);
  ASSERT_TRUE(client.find_server(5s));
  model::Command command;
  command.verb = "obstacle";
  command.target = "O1";
  command.value = "on";
  const auto reply = client.send_command(command, 5s);
  ASSERT_TRUE(reply && reply->accepted) << (reply ? reply->error : "no reply");
  fleet.start_agent("fl3");
  EXPECT_TRUE(eventually(
      [&] { return fleet.log_of("fleet-agent-fl3").find("static obstacle O1 enabled") != std::string::npos; }, 10s))
      << fleet.log_of("fleet-agent-fl3");
}

TEST(Recovery, FrozenAgentMissesItsDeadlineIsStalledThenLostAndComesBack) {
  FleetHarness fleet(77, 10.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));
  std::this_thread::sleep_for(500ms);
  const auto frozen = std::chrono::steady_clock::now();
  fleet.processes().signal(1, SIGSTOP);  // the agent, frozen as a stuck process would be
  // The RobotState deadline (0.5 s) names the robot stalled before its 1 s lease expires.
  ASSERT_TRUE(
      eventually([&] { return fleet.log_of("fleet-server").find("robot fl1 stalled") != std::string::npos; }, 3s))
      << fleet.log_of("fleet-server");
  const double stalled_after = std::chrono::duration<double>(std::chrono::steady_clock::now() - frozen).count();
  EXPECT_LT(stalled_after, 1.5);
  ASSERT_TRUE(eventually([&] { return fleet.log_of("fleet-server").find("robot fl1 lost") != std::string::npos; }, 5s));
  const std::string log = fleet.log_of("fleet-server");
  EXPECT_LT(log.find("robot fl1 stalled"), log.find("robot fl1 lost")) << log;
  fleet.processes().signal(1, SIGCONT);
  EXPECT_TRUE(eventually(
      [&] {
        const std::string after = fleet.log_of("fleet-server");
        return after.find("robot fl1 (forklifts) is back") != std::string::npos;
      },
      10s))
      << fleet.log_of("fleet-server");
}

// A robot whose messages are late after a server restart (a frozen process here; a secured
// handshake over a lossy link in a plant) keeps its body where it last stood in the restarted
// server's traffic control, so that no robot is granted a place it stands on meanwhile.
TEST(Recovery, ARestartedServerHoldsTheBodyOfARobotNotHeardFromYetWhereItLastStood) {
  FleetHarness fleet(96, 10.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));
  std::this_thread::sleep_for(500ms);  // its pose stored (at most every 0.1 s)
  fleet.processes().signal(1, SIGSTOP);
  fleet.processes().signal(0, SIGKILL);
  fleet.processes().reap();
  fleet.processes().restart(0);
  // fl1 stands at its home H1, (0.83, 0.82).
  const std::regex held(
      R"(robot fl1 not heard from yet: its body is held where it last stood \(([-\d.]+), ([-\d.]+)\))");
  std::string log;  // outlives the match, which points into it
  std::smatch where;
  ASSERT_TRUE(eventually(
      [&] {
        log = fleet.log_of("fleet-server");
        return std::regex_search(log, where, held);
      },
      10s))
      << fleet.log_of("fleet-server");
  EXPECT_NEAR(std::stod(where[1]), 0.83, 0.05);
  EXPECT_NEAR(std::stod(where[2]), 0.82, 0.05);
  fleet.processes().signal(1, SIGCONT);
  EXPECT_TRUE(eventually(
      [&] { return fleet.log_of("fleet-server").find("robot fl1 (forklifts) registered") != std::string::npos; }, 10s))
      << fleet.log_of("fleet-server");
}

TEST(Recovery, ASearchThatMissesARecordedPalletLeavesItsAreaOccupied) {
  // A robot whose camera misses the pallet at A1 (an estimate off by more than the search's match
  // radius, a marker out of view) reports the area empty. The server put that pallet there: it
  // must not take A1 for free, or the next order would put a second pallet on the first.
  ScriptedFleet s(79);
  const auto assignment = s.start_with_order();
  ASSERT_TRUE(assignment.has_value()) << s.server_log();
  const std::int64_t id = assignment->order_id;
  s.robot.report(*assignment, "ACCEPTED");
  s.robot.report(*assignment, "FAILED", "loading area A1 is empty (no marker in view)");
  ASSERT_TRUE(s.robot.keeps_answering_until([&] { return order_in_state(s.client, id, "FAILED"); }, 10s))
      << s.server_log();

  EXPECT_NE(s.server_log().find("found loading area A1 empty, but pallet"), std::string::npos) << s.server_log();
  model::OrderRequest onto_a1;
  onto_a1.pick_area = "A3";
  onto_a1.drop_area = "A1";
  const auto refused = s.client.request_order(onto_a1, 5s);
  ASSERT_TRUE(refused.has_value());
  EXPECT_FALSE(refused->accepted);
  EXPECT_NE(refused->error.find("loading area 'A1' holds a pallet"), std::string::npos) << refused->error;
}

TEST(Recovery, RobotLostWhileSearchingKeepsItsOrderAndCarriesOnWhenBack) {
  // A robot stalled while it searches at the pick area may find and lift the pallet within a
  // second of answering again, before a withdrawal reaches it. Re-queued, the order was withdrawn
  // from it with the pallet on its forks, and it stood in the lane for good. The server waits for
  // it instead, as for a robot lost while picking.
  ScriptedFleet s(86);
  const auto assignment = s.start_on_the_way_to_pick();
  ASSERT_TRUE(assignment.has_value()) << s.server_log();
  const std::int64_t id = assignment->order_id;
  s.robot.state.task_state = "SEARCH_PALLET";
  s.robot.report(*assignment, "SEARCHING");
  ASSERT_TRUE(s.order_reaches(id, "SEARCHING")) << s.server_log();

  // Frozen: silent past the 1 s after which the server counts it lost.
  ASSERT_TRUE(eventually([&] { return s.server_log().find("robot fl1 lost") != std::string::npos; }, 10s))
      << s.server_log();
  EXPECT_NE(s.server_log().find("waits for robot fl1: lost at the pick area"), std::string::npos) << s.server_log();

  // Back, it lifts the pallet and drives off with it on the order it was given.
  s.robot.state.task_state = "PICK_PALLET";
  s.robot.report(*assignment, "PICKING");
  s.robot.state.carrying_pallet = true;
  s.robot.state.task_state = "TRACK_PATH";
  s.robot.report(*assignment, "TO_DROP");
  EXPECT_TRUE(s.order_reaches(id, "TO_DROP")) << s.server_log();
  EXPECT_EQ(s.server_log().find("re-queued"), std::string::npos) << s.server_log();
}

TEST(Recovery, RobotThatLiftedThePalletOfItsRequeuedOrderGetsTheOrderBack) {
  // Lost on its way to the pick, a robot has its order re-queued and withdrawn. Answering again,
  // it reaches the pick area, searches and lifts the pallet before the withdrawal reaches it
  // (all within half a second of wall time at time scale 10). It cannot put the pallet back and
  // carries the order on; the server gives the order back to it.
  ScriptedFleet s(87);
  const auto first = s.start_on_the_way_to_pick();
  ASSERT_TRUE(first.has_value()) << s.server_log();
  const std::int64_t id = first->order_id;

  // Silent: lost, and the order is re-queued (no other robot to take it).
  ASSERT_TRUE(eventually(
      [&] { return s.server_log().find("order " + std::to_string(id) + " re-queued") != std::string::npos; }, 10s))
      << s.server_log();

  // Back with the pallet lifted, still on the first assignment.
  s.robot.report(*first, "SEARCHING");
  s.robot.report(*first, "PICKING");
  s.robot.state.carrying_pallet = true;
  s.robot.report(*first, "TO_DROP");
  std::optional<model::OrderAssignment> again;
  ASSERT_TRUE(s.robot.keeps_answering_until(
      [&] {
        s.robot.orders.take_data([&](model::OrderAssignment&& a) {
          if (a.order_id == id && a.robot_id == "fl1" && !a.cancelled && a.update_id > first->update_id) again = a;
        });
        return again.has_value();
      },
      10s))
      << s.server_log();
  s.robot.report(*again, "ACCEPTED");
  s.robot.report(*again, "TO_DROP");
  EXPECT_TRUE(s.order_reaches(id, "TO_DROP")) << s.server_log();
  EXPECT_NE(s.server_log().find("lifted by fl1 from A1"), std::string::npos) << s.server_log();
}

TEST(TrafficRecovery, RouteReplannedBeforeSettingOffReplacesTheOldOneInTheManager) {
  // fl1, admitted from home H1, replans before it sets off (an obstacle toggled) onto a route that
  // starts at another graph point, where fl2 stands: it waits to enter there. Were its first route
  // kept and granted meanwhile, others would wait on the places of a route nobody drives, and fl1
  // on them: a wait the manager's cycle detection cannot see.
  TableARoutes routes;
  const int h1_entry = routes.point_near(0.83, 0.82);
  const int h2_entry = routes.point_near(2.17, 0.82);
  const int a1_stop = routes.point_near(0.975, 0.45);
  const int a4_stop = routes.point_near(2.55, 2.025);
  const std::vector<int> first = routes.shortest(h1_entry, a1_stop);
  const std::vector<int> replanned = routes.shortest(h2_entry, a1_stop);
  const std::vector<int> fl2_route = routes.shortest(h2_entry, a4_stop);
  ASSERT_GE(first.size(), 2u);
  ASSERT_GE(replanned.size(), 2u);
  ASSERT_GE(fl2_route.size(), 2u);
  ASSERT_NE(h1_entry, h2_entry);

  ScriptedFleet s(88);
  s.fleet.start_server();
  ASSERT_TRUE(s.client.find_server(5s));
  ScriptedRobot fl2(s.client, "fl2", {2.17, 0.82, -1.57});  // home H2
  ASSERT_TRUE(s.robot.registers_with(s.fleet)) << s.server_log();
  ASSERT_TRUE(fl2.registers_with(s.fleet)) << s.server_log();
  dds::Writer<model::TrafficRequest> requests(s.client.participant(), dds::qos::live_state());
  dds::Reader<model::TrafficGrant> grants(s.client.participant(), dds::qos::live_state(),
                                          model::every_robot_partition());
  const auto both_answer = [&] {
    s.robot.publish_state();
    fl2.publish_state();
  };
  const auto request = [&](const std::string& robot, std::uint64_t version, const std::vector<int>& points) {
    requests.write({robot, version, points, 0.0, {}, 0.0, {}, {}, {}, "table_a"});
  };
  // Waits, both robots answering and `send` repeated as an agent does, for a grant to `robot` that
  // `wanted` accepts; every grant seen on the way goes to `seen`.
  const auto grant_to = [&](const std::string& robot, const std::function<void()>& send,
                            const std::function<bool(const model::TrafficGrant&)>& wanted,
                            std::vector<model::TrafficGrant>* seen = nullptr, std::chrono::milliseconds timeout = 10s) {
    bool found = false;
    eventually(
        [&] {
          both_answer();
          send();
          grants.take_data([&](model::TrafficGrant&& g) {
            if (g.robot_id != robot) return;
            if (wanted(g)) found = true;
            if (seen) seen->push_back(g);
          });
          return found;
        },
        timeout);
    return found;
  };

  // fl1 is admitted from H1 onto its first route.
  constexpr std::uint64_t kFirst = 16, kReplanned = 32, kFl2 = 48;
  ASSERT_TRUE(grant_to(
      "fl1", [&] { request("fl1", kFirst, first); },
      [&](const auto& g) { return g.version == kFirst && g.status == "MOVING"; }))
      << s.server_log();
  // fl2 drives onto the road at H2's entry.
  ASSERT_TRUE(grant_to(
      "fl2", [&] { request("fl2", kFl2, fl2_route); },
      [&](const auto& g) { return g.version == kFl2 && g.granted_index >= 0; }))
      << s.server_log();
  // fl1 replans from there, before it set off: it waits for fl2 beside the road, and from then on
  // only the replanned route is fl1's: nothing more is granted on the first.
  std::vector<model::TrafficGrant> seen;
  grant_to(
      "fl1", [&] { request("fl1", kReplanned, replanned); }, [](const auto&) { return false; }, &seen, 3s);
  const auto replanned_from =
      std::find_if(seen.begin(), seen.end(), [](const auto& g) { return g.version == kReplanned; });
  const auto on_first = [](const auto& g) { return g.version == kFirst; };
  ASSERT_FALSE(seen.empty()) << s.server_log();
  EXPECT_NE(replanned_from, seen.end()) << "fl1 granted only its first route, "
                                        << std::count_if(seen.begin(), seen.end(), on_first) << " times";
  EXPECT_EQ(std::count_if(replanned_from, seen.end(), on_first), 0)
      << "of " << seen.end() - replanned_from << " grants to fl1 since the replanned route";
  EXPECT_EQ(seen.back().version, kReplanned);
  EXPECT_EQ(seen.back().status, "WAITING");
  EXPECT_EQ(seen.back().blocked_by, std::vector<std::string>{"fl2"});
  // fl2 drives off the road back into its home: fl1 enters on the replanned route.
  ASSERT_TRUE(grant_to(
      "fl1",
      [&] {
        request("fl2", kFl2 + 16, {});
        request("fl1", kReplanned, replanned);
      },
      [&](const auto& g) { return g.version == kReplanned && g.status == "MOVING"; }))
      << s.server_log();
}
