// fleetctl commands against a real fleet-server and agent over DDS.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "fleet_harness.hpp"

using namespace fleet::testing;
using nlohmann::json;

namespace {
json last_json_line(const std::string& text) {
  const auto end = text.find_last_not_of('\n');
  const auto start = text.rfind('\n', end);
  const std::size_t from = start == std::string::npos ? 0 : start + 1;
  return json::parse(text.substr(from, end - from + 1));
}
}  // namespace

TEST(Fleetctl, StatsCountOrdersAndRoutingAgeComparesDirectAndRoutedPoses) {
  FleetHarness fleet(67, 10.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));
  const auto order = fleet.fleetctl({"order", "add", "--from", "A1", "--to", "A2", "--wait"}, 120);
  ASSERT_EQ(order.exit_code, 0) << order.err;

  const auto stats = fleet.fleetctl({"--json", "stats"}, 30);
  ASSERT_EQ(stats.exit_code, 0) << stats.err;
  const json s = last_json_line(stats.out);
  EXPECT_EQ(s["orders_by_state"]["DONE"], 1);
  EXPECT_GT(s["order_time_mean_s"].get<double>(), 0.0);
  EXPECT_GT(s["utilisation"]["fl1"].get<double>(), 0.0);
  EXPECT_LE(s["utilisation"]["fl1"].get<double>(), 1.0);

  const auto age = fleet.fleetctl({"--json", "routing-age", "--seconds", "2"}, 30);
  ASSERT_EQ(age.exit_code, 0) << age.err;
  const json a = last_json_line(age.out);
  EXPECT_GT(a["direct_samples"].get<int>(), 10);
  EXPECT_GT(a["routed_samples"].get<int>(), 10);
  // Routed poses are older: they went through the server first.
  EXPECT_GE(a["routed_age_median_ms"].get<double>(), a["direct_age_median_ms"].get<double>());
}

TEST(Fleetctl, StatsWithNoServerExits3) {
  const auto r = run_command({bin("fleetctl"), "--domain", "68", "--timeout", "1", "stats"}, 30);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("no fleet-server on DDS domain 68"), std::string::npos) << r.err;
}

TEST(Fleetctl, OrderListShowAndCancelWithTheirExitCodes) {
  FleetHarness fleet(69, 10.0);
  fleet.start_server();  // no robot: the order stays queued until it is cancelled
  const auto added = fleet.fleetctl({"order", "add", "--from", "A1", "--to", "A2"}, 30);
  ASSERT_EQ(added.exit_code, 0) << added.err;
  const std::string id = added.out.substr(0, added.out.find('\n'));

  const auto queued = fleet.fleetctl({"--json", "order", "list", "--state", "QUEUED"}, 30);
  ASSERT_EQ(queued.exit_code, 0) << queued.err;
  ASSERT_EQ(last_json_line(queued.out).size(), 1u) << queued.out;

  EXPECT_EQ(fleet.fleetctl({"order", "cancel", id}, 30).exit_code, 0);
  const auto again = fleet.fleetctl({"order", "cancel", id}, 30);
  EXPECT_EQ(again.exit_code, 1) << again.err;  // it ran and failed: already CANCELLED
  EXPECT_NE(again.err.find("already CANCELLED"), std::string::npos) << again.err;
  EXPECT_EQ(fleet.fleetctl({"order", "cancel", "999"}, 30).exit_code, 2);
  EXPECT_EQ(fleet.fleetctl({"order", "cancel", "abc"}, 30).exit_code, 2);

  const auto shown = fleet.fleetctl({"--json", "order", "show", id}, 30);
  ASSERT_EQ(shown.exit_code, 0) << shown.err;
  const json o = last_json_line(shown.out);
  EXPECT_EQ(o["state"], "CANCELLED");
  EXPECT_EQ(o["history"].front()["state"], "QUEUED");
  EXPECT_EQ(o["history"].back()["state"], "CANCELLED");
  EXPECT_EQ(fleet.fleetctl({"order", "show", "999"}, 30).exit_code, 2);
}

TEST(Fleetctl, ObstaclesPauseResumeAndMapsReachTheFleet) {
  FleetHarness fleet(73, 10.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1"}));

  EXPECT_EQ(fleet.fleetctl({"obstacle", "on", "O2"}, 30).exit_code, 0);
  const auto listed = fleet.fleetctl({"--json", "obstacle", "list"}, 30);
  ASSERT_EQ(listed.exit_code, 0) << listed.err;
  bool o2_on = false;
  for (const auto& row : last_json_line(listed.out)) o2_on = o2_on || (row["obstacle_id"] == "O2" && row["enabled"] == true);
  EXPECT_TRUE(o2_on) << listed.out;
  const auto unknown = fleet.fleetctl({"obstacle", "on", "O99"}, 30);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("'O99'"), std::string::npos) << unknown.err;

  EXPECT_EQ(fleet.fleetctl({"pause", "fl1"}, 30).exit_code, 0);
  bool paused = false;
  for (int i = 0; i < 50 && !paused; ++i) {
    const auto robots = fleet.fleetctl({"--json", "robots"}, 30);
    for (const auto& r : last_json_line(robots.out)) paused = paused || (r["robot_id"] == "fl1" && r.value("state", "") == "PAUSED");
  }
  EXPECT_TRUE(paused);
  EXPECT_EQ(fleet.fleetctl({"resume", "fl1"}, 30).exit_code, 0);
  EXPECT_EQ(fleet.fleetctl({"pause", "fl9"}, 30).exit_code, 2);

  const auto maps = fleet.fleetctl({"--json", "map", "list"}, 30);
  ASSERT_EQ(maps.exit_code, 0) << maps.err;
  EXPECT_EQ(last_json_line(maps.out)["site"], "table_a");
}
