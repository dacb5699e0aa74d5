// Fleet's robots as VDA 5050 vehicles (`fleet-agent --vda5050`) over a real mosquitto broker:
// under a foreign master control, vda-5050-lib's MasterController (tests/vda5050/foreign_master.js),
// with no fleet-server; and under Fleet's own master control (fleet-vda5050) speaking 2.1.0.

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli/vda5050_vehicles.hpp"
#include "config/fleet_config.hpp"
#include "fleet_harness.hpp"
#include "map/site_map.hpp"
#include "message_check.hpp"
#include "test_paths.hpp"
#include "vda5050/vehicle_drive.hpp"

using namespace fleet::testing;
using nlohmann::json;

namespace {

const std::string kConfig = fleet::test::source_dir() + "/config/sites/table_a-vda5050.yaml";

/// The lines of a JSON-lines log with "event" == `event`.
std::vector<json> events(const std::string& log, const std::string& event) {
  std::vector<json> out;
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);) {
    const json j = json::parse(line, nullptr, false);
    if (j.is_object() && j.value("event", "") == event) out.push_back(j);
  }
  return out;
}

/// Waits until `log` has a line of `event` (true) or of "fail" or `timeout_s` passes (false).
bool wait_for_event(const std::string& log, const std::string& event, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    if (!events(log, event).empty()) return true;
    if (!events(log, "fail").empty()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return false;
}

json node_of(const std::string& id, const fleet::geometry::Pose2& pose, bool with_theta) {
  json node = {{"id", id}, {"x", pose.x}, {"y", pose.y}};
  if (with_theta) node["theta"] = pose.yaw;
  return node;
}

int nearest_point(const fleet::map::RoadGraph& graph, fleet::geometry::Vec2 at) {
  int best = 0;
  for (const auto& p : graph.points) {
    if (fleet::geometry::distance({p.x, p.y}, at) <
        fleet::geometry::distance(
            {graph.points[static_cast<std::size_t>(best)].x, graph.points[static_cast<std::size_t>(best)].y}, at)) {
      best = p.id;
    }
  }
  return best;
}

/// fl1's way from its home H1 to A1, drop at A2; `middle` a road point halfway to A1.
json scenario(const std::string& serial) {
  const fleet::map::SiteMap site = fleet::map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto& graph = site.graph.graph;
  const auto* home = site.site.find_home("H1");
  const auto* pick = site.site.find_area("A1");
  const auto* drop = site.site.find_area("A2");
  const std::vector<int> way = fleet::vda5050::shortest_road(graph, nearest_point(graph, home->pose.position()),
                                                             nearest_point(graph, pick->pose.position()));
  const int middle = way.at(way.size() / 2);
  const auto& m = graph.points[static_cast<std::size_t>(middle)];
  std::string middle_id = "p";
  middle_id += std::to_string(middle);
  return {{"interface", "uagv"},
          {"manufacturer", "Fleet"},
          {"serial", serial},
          {"map", "table_a"},
          {"start", node_of("H1", home->pose, true)},
          {"middle", node_of(middle_id, {m.x, m.y, 0.0}, false)},
          {"pick", node_of("A1", pick->pose, true)},
          {"drop", node_of("A2", drop->pose, true)}};
}

}  // namespace

TEST(Vda5050, AForeignMasterDrivesAFleetRobotThroughBaseUpdatesAndErrors) {
  FleetHarness fleet(114, 1.0);
  auto& processes = fleet.processes();
  const std::string broker = fleet::cli::start_mqtt_broker(processes, fleet.log_dir());
  const std::string mqtt_url = mqtt_url_of(broker);
  // Every message the vehicle publishes, checked.
  const std::size_t checker = start_message_check(fleet, mqtt_url, "state,connection,visualization");

  const std::size_t agent = processes.start(
      "fleet-agent fl1",
      {bin("fleet-agent"), "--config", kConfig, "--id", "fl1", "--time-scale", "3", "--vda5050", broker},
      fleet.log_dir() + "/fleet-agent-fl1.log");
  const std::string scenario_file = fleet.log_dir() + "/scenario.json";
  std::ofstream(scenario_file) << scenario("fl1").dump(2);
  const std::string master_log = fleet.log_dir() + "/foreign-master.log";
  processes.start("foreign master",
                  {"node", fleet::test::source_dir() + "/tests/vda5050/foreign_master.js", "--broker", mqtt_url,
                   "--scenario", scenario_file},
                  master_log);

  ASSERT_TRUE(wait_for_event(master_log, "online", 60)) << "see " << master_log;
  ASSERT_TRUE(wait_for_event(master_log, "base_end", 120)) << "see " << master_log;
  EXPECT_EQ(events(master_log, "base_end").front()["horizon"], 2);
  ASSERT_TRUE(wait_for_event(master_log, "finished", 300)) << "see " << master_log;
  EXPECT_EQ(events(master_log, "finished").front()["lastNodeId"], "A2");
  ASSERT_TRUE(wait_for_event(master_log, "passed", 60)) << "see " << master_log;
  const json refused = events(master_log, "rejected").front()["errors"];
  ASSERT_EQ(refused.size(), 4u);
  const std::vector<std::string> types{"orderUpdateError", "orderUpdateError", "orderError", "noOrderToCancel"};
  for (std::size_t i = 0; i < types.size(); ++i) {
    EXPECT_EQ(refused[i].value("errorType", ""), types[i]) << refused.dump();
    EXPECT_FALSE(refused[i].value("errorDescription", "").empty()) << refused.dump();
  }
  EXPECT_TRUE(events(master_log, "malformed_state").empty()) << "see " << master_log;

  // Killed, the vehicle's last will reaches the master: CONNECTIONBROKEN.
  processes.signal(agent, SIGKILL);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  bool broken = false;
  while (!broken && std::chrono::steady_clock::now() < deadline) {
    for (const json& c : events(master_log, "connection")) broken = broken || c["state"] == "CONNECTIONBROKEN";
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_TRUE(broken) << "see " << master_log;

  const json result = message_check_result(fleet, checker);
  EXPECT_GT(result.value("checked", 0), 10) << result.dump();
  EXPECT_EQ(result.value("invalid_count", -1), 0) << result.dump();
}

TEST(Vda5050, FleetAsMasterDrivesFleetRobotsAsVehiclesIn2_1_0) {
  // fleet-server and fleet-vda5050 see two VDA 5050 vehicles of maker Fleet; each is a forklift
  // of table_a-vda5050.yaml run by `fleet-agent --vda5050 --vda5050-version 2.1.0`.
  FleetHarness fleet(115, 3.0);
  fleet.use_config(fleet::test::source_dir() + "/config/sites/table_a-vda5050-fleet.yaml");
  auto& processes = fleet.processes();
  const std::string broker = fleet::cli::start_mqtt_broker(processes, fleet.log_dir());
  const std::string mqtt_url = mqtt_url_of(broker);
  const std::size_t checker =
      start_message_check(fleet, mqtt_url, "order,instantActions,state,connection,visualization");
  fleet.start_server();
  std::vector<std::string> bridge{bin("fleet-vda5050")};
  for (const auto& a : fleet.common_args()) bridge.push_back(a);
  bridge.insert(bridge.end(), {"--broker", broker});
  processes.start("fleet-vda5050", bridge, fleet.log_dir() + "/fleet-vda5050.log");
  for (const std::string id : {"fl1", "fl2"}) {
    processes.start("fleet-agent " + id,
                    {bin("fleet-agent"), "--config", kConfig, "--id", id, "--time-scale", "3", "--vda5050", broker,
                     "--vda5050-version", "2.1.0"},
                    fleet.log_dir() + "/fleet-agent-" + id + ".log");
  }
  ASSERT_TRUE(fleet.wait_for_robots({"f1", "f2"}, 60)) << "see " << fleet.log_dir();

  std::vector<std::int64_t> ids;
  for (const auto& [from, to] : {std::pair{"A1", "A2"}, std::pair{"A5", "A6"}}) {
    const auto added = fleet.fleetctl({"--json", "order", "add", "--from", from, "--to", to});
    ASSERT_EQ(added.exit_code, 0) << added.out << added.err;
    ids.push_back(last_json_line(added.out)["order_id"]);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(240);
  std::vector<std::string> status(ids.size());
  while (std::chrono::steady_clock::now() < deadline) {
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const auto shown = fleet.fleetctl({"--json", "order", "show", std::to_string(ids[i])}, 30);
      if (shown.exit_code == 0) status[i] = last_json_line(shown.out).value("state", "");
    }
    if (std::all_of(status.begin(), status.end(), [](const std::string& s) { return s == "DONE" || s == "FAILED"; })) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::seconds(1));
  }
  for (std::size_t i = 0; i < ids.size(); ++i)
    EXPECT_EQ(status[i], "DONE") << "order " << ids[i] << ": see " << fleet.log_dir();

  // Both sides' messages, Fleet's orders and its vehicles' states, against the 2.1.0 schemas.
  const json result = message_check_result(fleet, checker);
  EXPECT_GT(result.value("checked", 0), 20) << result.dump();
  EXPECT_EQ(result.value("invalid_count", -1), 0) << result.dump();
}
