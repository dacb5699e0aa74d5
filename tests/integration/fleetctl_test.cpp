// fleetctl commands against a real fleet-server and agent over DDS.

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "fleet_harness.hpp"

using namespace fleet::testing;
using nlohmann::json;

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
  EXPECT_EQ(fleet.fleetctl({"pause", "fl99"}, 30).exit_code, 2);

  const auto maps = fleet.fleetctl({"--json", "map", "list"}, 30);
  ASSERT_EQ(maps.exit_code, 0) << maps.err;
  EXPECT_EQ(last_json_line(maps.out)["site"], "table_a");

  // traffic show: once the robot drives an order, its grant and the route points granted.
  ASSERT_EQ(fleet.fleetctl({"order", "add", "--from", "A1", "--to", "A2"}, 30).exit_code, 0);
  json shown;
  for (int i = 0; i < 40 && !shown.contains("granted_points"); ++i) {
    const auto traffic = fleet.fleetctl({"--json", "traffic", "show", "fl1"}, 30);
    ASSERT_EQ(traffic.exit_code, 0) << traffic.err;
    shown = last_json_line(traffic.out);
  }
  ASSERT_TRUE(shown.contains("granted_points")) << shown;
  EXPECT_FALSE(shown["granted_points"].empty());
  EXPECT_EQ(shown["wait_chain"], "fl1 waits for nobody");
  const auto table = fleet.fleetctl({"traffic", "show"}, 30);
  EXPECT_NE(table.out.find("fl1"), std::string::npos) << table.out;
  EXPECT_EQ(fleet.fleetctl({"traffic", "show", "fl99"}, 30).exit_code, 2);
  EXPECT_EQ(fleet.fleetctl({"traffic", "list"}, 30).exit_code, 2);
}

// ---- order watch, inject and completion (DDS domains 80-89) ----

namespace {
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(line);
  }
  return lines;
}

/// A file in this test's temporary folder with `text` in it.
std::string write_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / ("fleetctl-test-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

/// The (from, to) pairs of an inject summary.
std::vector<std::string> routes_of(const json& summary) {
  std::vector<std::string> routes;
  for (const auto& o : summary["orders"])
    routes.push_back(o["pick_area"].get<std::string>() + ">" + o["drop_area"].get<std::string>());
  return routes;
}
}  // namespace

TEST(Fleetctl, HelpListsEveryCommandAndTheExitCodes) {
  const auto r = run_command({bin("fleetctl"), "--help"}, 30);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* text :
       {"order watch [ID]", "inject [--count M] [--rate N/min]", "completion bash", "order add", "demo", "map check",
        "config keys", "0  ok", "1  the operation ran and failed", "2  bad input", "3  no fleet-server reachable"}) {
    EXPECT_NE(r.out.find(text), std::string::npos) << text;
  }
  const auto unknown = run_command({bin("fleetctl"), "injekt"}, 30);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("unknown command 'injekt'"), std::string::npos) << unknown.err;
}

TEST(Fleetctl, CompletionBashLoadsAndCompletesPartialWords) {
  const std::string script = "source <(" + bin("fleetctl") +
                             " completion bash) || exit 9\n"
                             "complete -p fleetctl\n"
                             "complete_line() { COMP_WORDS=(\"$@\"); COMP_CWORD=$(( $# - 1 )); COMPREPLY=(); "
                             "_fleetctl; echo \"${COMPREPLY[*]}\"; }\n"
                             "complete_line fleetctl or\n"
                             "complete_line fleetctl order w\n"
                             "complete_line fleetctl --domain 81 inject --ra\n"
                             "complete_line fleetctl order list --state D\n"
                             "complete_line fleetctl --js\n";
  const auto r = run_command({"/bin/bash", "-c", script}, 30);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), 6u) << r.out;
  EXPECT_EQ(lines[0], "complete -F _fleetctl fleetctl");
  EXPECT_EQ(lines[1], "order");
  EXPECT_EQ(lines[2], "watch");
  EXPECT_EQ(lines[3], "--rate");
  EXPECT_EQ(lines[4], "DONE");
  EXPECT_EQ(lines[5], "--json");
  const auto as_json = run_command({bin("fleetctl"), "--json", "completion", "bash"}, 30);
  ASSERT_EQ(as_json.exit_code, 0) << as_json.err;
  EXPECT_EQ(last_json_line(as_json.out)["shell"], "bash");
}

TEST(Fleetctl, InjectFromCsvChecksTheWholeFileFirstAndSendsAllOrNothing) {
  FleetHarness fleet(82, 10.0);
  fleet.start_server();  // no robot: injected orders stay queued
  const std::string bad = write_file("bad.csv",
                                     "# two bad rows after a good one\n"
                                     "from,to,priority,delay_s\n"
                                     "A1,A2,0,0\n"
                                     "A3,A9,0,0\n"
                                     "A5,A6,0,-2\n");
  const auto refused = fleet.fleetctl({"inject", "--file", bad}, 60);
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_NE(refused.err.find("bad.csv:4: to: unknown loading area 'A9'; valid: A1, A2"), std::string::npos)
      << refused.err;
  EXPECT_NE(refused.err.find("bad.csv:5: delay_s -2 is negative"), std::string::npos) << refused.err;
  EXPECT_EQ(refused.err.find("bad.csv:3:"), std::string::npos) << refused.err;
  const auto none = fleet.fleetctl({"--json", "order", "list"}, 30);
  ASSERT_EQ(none.exit_code, 0) << none.err;
  EXPECT_EQ(last_json_line(none.out).size(), 0u) << none.out;  // not even line 3 went out

  const std::string good = write_file("good.csv",
                                      "from,to,priority,delay_s\n"
                                      "A1,A2,0,0\n"
                                      "A3,A4,5,0.2\n"
                                      "# picks the pallet line 2 brings to A2\n"
                                      "A2,A6,0,0\n");
  const auto injected = fleet.fleetctl({"--json", "inject", "--file", good}, 60);
  ASSERT_EQ(injected.exit_code, 0) << injected.err;
  const json summary = last_json_line(injected.out);
  EXPECT_EQ(summary["placed"], 3);
  EXPECT_EQ(routes_of(summary), (std::vector<std::string>{"A1>A2", "A3>A4", "A2>A6"}));
  EXPECT_EQ(summary["orders"][1]["line"], 3);
  EXPECT_EQ(summary["orders"][1]["priority"], 5);
  EXPECT_EQ(lines_of(injected.out).size(), 4u) << injected.out;  // one line per order, then the summary
  const auto listed = fleet.fleetctl({"--json", "order", "list"}, 30);
  EXPECT_EQ(last_json_line(listed.out).size(), 3u) << listed.out;
}

TEST(Fleetctl, InjectIsTheSameForTheSameSeedAndRefusesBadFlags) {
  FleetHarness fleet(83, 10.0);
  fleet.start_server();
  const std::vector<std::string> inject{"--json", "inject", "--count", "3", "--rate", "600/min", "--seed", "7"};
  const auto first = fleet.fleetctl(inject, 60);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const json summary = last_json_line(first.out);
  ASSERT_EQ(summary["placed"], 3) << first.out;
  for (const auto& o : summary["orders"]) {
    EXPECT_NE(o["pick_area"], o["drop_area"]);
    EXPECT_EQ(fleet.fleetctl({"order", "cancel", std::to_string(o["order_id"].get<long>())}, 30).exit_code, 0);
  }
  // Cancelled orders promise nothing: the fleet's pallets are as before, so the seed draws the same.
  const auto second = fleet.fleetctl(inject, 60);
  ASSERT_EQ(second.exit_code, 0) << second.err;
  EXPECT_EQ(routes_of(last_json_line(second.out)), routes_of(summary));

  EXPECT_EQ(fleet.fleetctl({"inject"}, 30).exit_code, 2);
  EXPECT_EQ(fleet.fleetctl({"inject", "--count", "2", "--rate", "fast"}, 30).exit_code, 2);
  EXPECT_EQ(fleet.fleetctl({"inject", "--file", "x.csv", "--count", "2"}, 30).exit_code, 2);
  const auto no_server =
      run_command({bin("fleetctl"), "--domain", "84", "--timeout", "1", "inject", "--count", "1"}, 30);
  EXPECT_EQ(no_server.exit_code, 3) << no_server.err;
  EXPECT_NE(no_server.err.find("no fleet-server on DDS domain 84"), std::string::npos) << no_server.err;
}

TEST(Fleetctl, OrderWatchAndInjectWaitFollowOrdersToTheirEnd) {
  FleetHarness fleet(85, 10.0);
  fleet.start_server();
  fleet.start_agent("fl1");
  fleet.start_agent("fl2");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1", "fl2"}));

  const auto added = fleet.fleetctl({"order", "add", "--from", "A1", "--to", "A2"}, 30);
  ASSERT_EQ(added.exit_code, 0) << added.err;
  const std::string id = added.out.substr(0, added.out.find('\n'));
  const auto watched = fleet.fleetctl({"order", "watch", id}, 120);
  const auto lines = lines_of(watched.out);
  ASSERT_GE(lines.size(), 2u) << watched.out << watched.err;
  for (const auto& line : lines) {
    EXPECT_EQ(line.rfind("order " + id + " A1 -> A2  ", 0), 0u) << line;  // plain lines when piped
    EXPECT_EQ(line.find('\x1b'), std::string::npos) << line;
  }
  EXPECT_NE(lines.front().find("left ?"), std::string::npos) << lines.front();  // no order has finished yet
  const bool done = lines.back().find(" DONE ") != std::string::npos;
  EXPECT_TRUE(done || lines.back().find(" FAILED ") != std::string::npos) << lines.back();
  EXPECT_EQ(watched.exit_code, done ? 0 : 1) << watched.err;

  const auto injected =
      fleet.fleetctl({"--json", "inject", "--count", "3", "--rate", "600/min", "--seed", "2", "--wait"}, 180);
  EXPECT_EQ(injected.exit_code, 0) << injected.err;
  const auto streamed = lines_of(injected.out);
  ASSERT_EQ(streamed.size(), 4u) << injected.out;  // one line per injected order, then the summary
  const json summary = last_json_line(injected.out);
  EXPECT_EQ(summary["placed"], 3);
  EXPECT_EQ(summary["lost"], 0);
  EXPECT_EQ(summary["open"], 0);
  for (const auto& o : summary["orders"]) {
    const std::string state = o["state"];
    EXPECT_TRUE(state == "DONE" || state == "FAILED") << o.dump();
    if (state == "FAILED") {
      EXPECT_FALSE(o["reason"].get<std::string>().empty()) << o.dump();
    }
  }

  // Watching an order that already ended prints it once and ends with its exit code.
  const json last = summary["orders"].back();
  const auto again = fleet.fleetctl({"--json", "order", "watch", std::to_string(last["order_id"].get<long>())}, 30);
  ASSERT_EQ(lines_of(again.out).size(), 1u) << again.out << again.err;
  EXPECT_EQ(last_json_line(again.out)["state"], last["state"]);
  EXPECT_EQ(again.exit_code, last["state"] == "DONE" ? 0 : 1);
  EXPECT_EQ(fleet.fleetctl({"order", "watch", "999"}, 30).exit_code, 2);
}
