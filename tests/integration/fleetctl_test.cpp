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
