// The short soak of scripts/test: four agents on table_a for three minutes of wall time at time
// scale 10, every fault on the seeded schedule, judged by the soak's own exit status and the
// figures of its JSON summary. It demands what docs/operations.md promises of a soak: nothing
// lost or run twice, no collision, no deadlock (an open order without progress for 60 s sim).

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "fleet_harness.hpp"
#include "test_paths.hpp"

using namespace fleet::testing;

TEST(Soak, FourAgentsUnderEveryFaultLoseNothingRunNothingTwiceCollideNeverAndDetectEveryFault) {
  FleetHarness fleet(75, 10.0);
  const auto run = fleet.fleetctl({"--json", "soak", "--agents", "4", "--site", "table_a", "--duration", "180",
                                   "--time-scale", "10", "--faults", "all", "--seed", "7"},
                                  420.0);
  // --json: the last line printed is the summary.
  std::string line;
  for (std::size_t end = run.out.size(); end > 0 && line.empty();) {
    const std::size_t start = run.out.rfind('\n', end - 1);
    const std::size_t from = start == std::string::npos ? 0 : start + 1;
    line = run.out.substr(from, end - from);
    end = start == std::string::npos ? 0 : start;
  }
  ASSERT_FALSE(line.empty()) << run.err;
  const auto summary = nlohmann::json::parse(line);
  std::cout << "soak summary: " << summary.dump() << "\n";
  EXPECT_EQ(run.exit_code, 0) << "soak failures: " << summary["failures"].dump();
  EXPECT_EQ(summary["collisions"], 0);
  EXPECT_EQ(summary["deadlocks"], 0);
  EXPECT_GE(summary["faults_injected"].get<int>(), 3);
  EXPECT_EQ(summary["orders_lost"], 0);
  EXPECT_EQ(summary["orders_duplicated"], 0);
  EXPECT_TRUE(summary["crashed"].empty()) << summary["crashed"].dump();
  EXPECT_EQ(summary["faults_undetected"], 0);
  EXPECT_TRUE(summary["robots_lost_without_a_fault"].empty()) << summary["robots_lost_without_a_fault"].dump();
  EXPECT_LE(summary["detect_latency_p95_s"].get<double>(), 1.5);
  for (const auto& [type, growth] : summary["rss_growth_pct"].items()) EXPECT_LE(growth.get<double>(), 10.0) << type;
  EXPECT_GT(summary["orders_done"].get<int>(), 0);
  // The agents reported how late their control steps ran (not judged at time scale 10).
  const auto& lag = summary["control_lag_worst"];
  ASSERT_TRUE(lag.contains("p99_s")) << lag.dump();
  EXPECT_NEAR(lag["period_s"].get<double>(), 1.0 / 70.0, 1e-3);
  EXPECT_GE(lag["p99_s"].get<double>(), lag["p50_s"].get<double>());
}

// fleetctl load: the real server against emulated robots; judged by its exit status and the
// figures every run must print.
TEST(Load, TwentyEmulatedRobotsAreServedAndMeasured) {
  FleetHarness fleet(76, 10.0);
  fleet.use_config(fleet::test::source_path("/config/sites/big_warehouse.yaml"));
  const auto run = fleet.fleetctl({"--json", "load", "--robots", "20", "--site", "big_warehouse", "--duration", "20",
                                   "--warmup", "5", "--time-scale", "5"},
                                  120.0);
  const auto line_start = run.out.rfind('\n', run.out.size() >= 2 ? run.out.size() - 2 : 0);
  const std::string line = run.out.substr(line_start == std::string::npos ? 0 : line_start + 1);
  ASSERT_FALSE(line.empty()) << run.err;
  const auto summary = nlohmann::json::parse(line);
  std::cout << "load summary: " << summary.dump() << "\n";
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(summary["robots_reported"], 20);
  EXPECT_EQ(summary["collisions"], 0);
  EXPECT_EQ(summary["deadlocks"], 0);
  EXPECT_GT(summary["traffic_cycles"].get<int>(), 0);
  EXPECT_GT(summary["routes_sent"].get<int>(), 0);
  EXPECT_EQ(summary["routes_unanswered"], 0);
  EXPECT_GT(summary["grant_latency_ms"]["p50"].get<double>(), 0.0);
  EXPECT_GT(summary["server_cpu_pct"].get<double>(), 0.0);
  EXPECT_GT(summary["samples_to_server_per_s"].get<double>(), 20.0 * 20.0);  // state and traffic at 20 Hz sim
  EXPECT_GT(summary["web_stream_bytes_per_s"].get<double>(), 0.0);
}

TEST(Load, MoreRobotsThanTheFleetDeclaresIsBadInput) {
  FleetHarness fleet(77, 10.0);
  fleet.use_config(fleet::test::source_path("/config/sites/big_warehouse.yaml"));
  const auto run = fleet.fleetctl({"load", "--robots", "601", "--site", "big_warehouse"}, 60.0);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("declares 600 robots"), std::string::npos) << run.err;
}
