// The walking skeleton end to end: real fleet-server, fleet-agent and fleetctl processes over DDS.

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "fleet_harness.hpp"
#include "map/site.hpp"
#include "test_paths.hpp"

using namespace fleet::testing;
using nlohmann::json;

namespace {

/// Processes whose command line mentions this DDS domain.
int fleet_processes_on_domain(int domain) {
  const auto r =
      run_command({"/usr/bin/pgrep", "-fc", "fleet-(server|agent).*--domain " + std::to_string(domain) + " "});
  return std::atoi(r.out.c_str());
}

}  // namespace

TEST(Skeleton, OrderGoesThroughItsLifecycleAndTheRobotEndsAtTheDropPose) {
  FleetHarness fleet(60, 10.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  fleet.start_agent("fl2");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1", "fl2"}));
  const auto r = fleet.fleetctl({"order", "add", "--from", "A1", "--to", "A2", "--wait", "--json"}, 120);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << fleet.log_of("fleet-server");
  const json order = last_json_line(r.out);
  EXPECT_EQ(order["state"], "DONE");

  // The lifecycle in order: QUEUED -> ASSIGNED -> ACTIVE (TO_PICK ... DROPPING) -> DONE.
  std::vector<std::string> states, phases;
  for (const auto& e : order["history"]) {
    states.push_back(e["state"]);
    phases.push_back(e["phase"]);
  }
  ASSERT_GE(states.size(), 4u) << order.dump();
  EXPECT_EQ(states.front(), "QUEUED");
  EXPECT_EQ(states[1], "ASSIGNED");
  EXPECT_EQ(states.back(), "DONE");
  for (const char* phase : {"TO_PICK", "PICKING", "TO_DROP", "DROPPING"}) {
    EXPECT_NE(std::find(phases.begin(), phases.end(), phase), phases.end()) << phase << " missing: " << order.dump();
  }
  // Ascending robot id [Forklift thesis, section 3]: fl1 takes the first order.
  EXPECT_EQ(order["robot_id"], "fl1");

  // At DONE the robot stands at area A2's service pose: 0.30 m out from the pallet along the
  // area's yaw (maps/table_a.yaml).
  const auto& done = order["history"].back();
  const auto site = fleet::map::load_site(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto* a2 = site.find_area("A2");
  ASSERT_NE(a2, nullptr);
  const double sx = a2->pose.x + 0.30 * std::cos(a2->pose.yaw);
  const double sy = a2->pose.y + 0.30 * std::sin(a2->pose.yaw);
  EXPECT_LT(std::hypot(done["robot_x"].get<double>() - sx, done["robot_y"].get<double>() - sy), 0.05) << done.dump();
}

TEST(Skeleton, UnknownAreaIsNamedWithTheValidOnesAndExits2) {
  FleetHarness fleet(61, 10.0);
  fleet.start_server();
  const auto r = fleet.fleetctl({"order", "add", "--from", "NOPE", "--to", "A2"}, 30);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("'NOPE'"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("A1"), std::string::npos) << r.err;
}

TEST(Skeleton, NoServerIsReportedWithinThreeSecondsWithExit3) {
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_command({bin("fleetctl"), "--domain", "62", "order", "add", "--from", "A1", "--to", "A2"}, 30);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("no fleet-server on DDS domain 62"), std::string::npos) << r.err;
  EXPECT_LT(took, 5.0);  // 3 s of looking plus process start; a functional bound, not a benchmark
}

TEST(Skeleton, UnknownConfigKeyNamesKeyAndFile) {
  const std::string path = ::testing::TempDir() + "/bad_fleet.yaml";
  std::ofstream(path) << "server:\n  dispatch_polcy: nearest\nfleets: []\n";
  for (const char* binary : {"fleet-server", "fleetctl"}) {
    const auto r = run_command({bin(binary), "--config", path, "--domain", "63", "robots"}, 30);
    EXPECT_EQ(r.exit_code, 2) << binary << ": " << r.err;
    EXPECT_NE(r.err.find("server.dispatch_polcy"), std::string::npos) << binary << ": " << r.err;
    EXPECT_NE(r.err.find(path), std::string::npos) << binary << ": " << r.err;
  }
}

TEST(Skeleton, DemoEndsByItselfWithOrdersDoneNoneLostAndNoProcessLeft) {
  const auto r = run_command({bin("fleetctl"), "--domain", "64", "demo", "--http-port", "0", "--agents", "2",
                              "--duration", "25", "--time-scale", "10", "--json"},
                             120);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const json summary = last_json_line(r.out);
  EXPECT_GE(summary["orders_done"].get<int>(), 1) << summary.dump();
  EXPECT_EQ(summary["orders_lost"].get<int>(), 0) << summary.dump();
  EXPECT_EQ(summary["agents"].get<int>(), 2);
  for (const char* key : {"orders_created", "orders_failed", "collisions", "sim_seconds"}) {
    EXPECT_TRUE(summary.contains(key)) << key;
  }
  EXPECT_EQ(fleet_processes_on_domain(64), 0);
}

TEST(Skeleton, DemoKilledWithSigtermLeavesNoChildBehind) {
  FleetHarness launcher(65, 10.0);
  launcher.processes().start(
      "fleetctl demo",
      {bin("fleetctl"), "--domain", "65", "demo", "--http-port", "0", "--agents", "2", "--time-scale", "10"},
      ::testing::TempDir() + "/demo65.log");
  // Wait for the fleet to be up.
  for (int i = 0; i < 100 && fleet_processes_on_domain(65) < 3; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(fleet_processes_on_domain(65), 3);
  launcher.processes().signal(0, SIGTERM);
  for (int i = 0; i < 100 && fleet_processes_on_domain(65) > 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(fleet_processes_on_domain(65), 0);
}

TEST(Skeleton, DemoKilledWithSigkillLeavesNoChildBehind) {
  FleetHarness launcher(66, 10.0);
  launcher.processes().start(
      "fleetctl demo",
      {bin("fleetctl"), "--domain", "66", "demo", "--http-port", "0", "--agents", "2", "--time-scale", "10"},
      ::testing::TempDir() + "/demo66.log");
  for (int i = 0; i < 100 && fleet_processes_on_domain(66) < 3; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  ASSERT_EQ(fleet_processes_on_domain(66), 3);
  launcher.processes().signal(0, SIGKILL);
  for (int i = 0; i < 100 && fleet_processes_on_domain(66) > 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(fleet_processes_on_domain(66), 0);
}
