// Fleet as VDA 5050 master control over a real mosquitto broker: vda-5050-lib's virtual vehicles
// beside Fleet's own agents on table_a (domains 111-113).

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli/vda5050_vehicles.hpp"
#include "config/fleet_config.hpp"
#include "fleet_harness.hpp"
#include "map/site.hpp"
#include "message_check.hpp"
#include "test_paths.hpp"

using namespace fleet::testing;
using nlohmann::json;

namespace {

const std::string kConfig = fleet::test::source_dir() + "/config/sites/table_a-vda5050.yaml";

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The order as `fleetctl order show --json` gives it.
json order_of(const FleetHarness& fleet, std::int64_t id) {
  const auto shown = fleet.fleetctl({"--json", "order", "show", std::to_string(id)}, 30);
  if (shown.exit_code != 0) return json::object();
  return last_json_line(shown.out);
}

/// Waits until `done(order)` holds for order `id`, polling; false after `timeout_s`.
bool wait_for_order(const FleetHarness& fleet, std::int64_t id, const std::function<bool(const json&)>& done,
                    double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    if (done(order_of(fleet, id))) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return false;
}

/// A fleet-server with the table_a-vda5050 configuration, and `vehicles` virtual VDA 5050 vehicles
/// with their broker and fleet-vda5050, all stopped with the harness.
struct VdaFleet {
  FleetHarness fleet;
  fleet::cli::Vda5050Vehicles vehicles;
  std::size_t vehicles_process = 0;

  /// At time scale 3: the vehicles drive their orders in a third of the wall time, and the losses
  /// the tests cause are found by wall-time leases all the same.
  static constexpr double kTimeScale = 3.0;

  VdaFleet(int domain, int count, const std::vector<std::string>& vehicle_args = {}) : fleet(domain, kTimeScale) {
    fleet.use_config(kConfig);
    fleet.start_server();
    fleet::config::FleetConfig config = fleet::config::load_fleet_config(kConfig);
    const fleet::map::Site site = fleet::map::load_site(fleet::test::source_dir() + "/maps/table_a.yaml");
    std::vector<std::string> bridge{bin("fleet-vda5050")};
    for (const auto& a : fleet.common_args()) bridge.push_back(a);
    vehicles = fleet::cli::start_vda5050_vehicles(fleet.processes(), config, site, count, kTimeScale, bridge,
                                                  fleet.log_dir(), vehicle_args);
    vehicles_process = fleet.processes().children().size() - 1;
  }

  /// A transport A5 -> A2 for the vehicles' fleet, taken and under way for a second (3 s sim); its id,
  /// 0 when it was not placed or not taken within 30 s.
  std::int64_t order_under_way() {
    const auto added = fleet.fleetctl({"--json", "order", "add", "--from", "A5", "--to", "A2", "--fleet", "visitors"});
    if (added.exit_code != 0) return 0;
    const std::int64_t id = last_json_line(added.out)["order_id"];
    if (!wait_for_order(
            fleet, id, [](const json& o) { return o.value("phase", "") == "TO_PICK"; }, 30))
      return 0;
    std::this_thread::sleep_for(std::chrono::seconds(1));
    return id;
  }

  std::size_t process_named(const std::string& name) {
    const auto& children = fleet.processes().children();
    for (std::size_t i = 0; i < children.size(); ++i) {
      if (children[i].name == name) return i;
    }
    return children.size();
  }
};

}  // namespace

TEST(Vda5050, VehiclesOfAnotherMakerAndFleetsOwnAgentsDoOrdersTogether) {
  // The soak's ground-truth watch reads the vehicles' reported positions (their SimTruth, from
  // fleet-vda5050) beside the agents' truth: 0 collisions, 0 deadlocks, nothing lost. Every
  // process runs with DDS Security, the bridge speaking for its vehicles in their partitions.
  std::string security = std::filesystem::temp_directory_path() / "fleet-vda-sec-";
  security += std::to_string(getpid());
  std::filesystem::remove_all(security);
  const auto init =
      run_command({bin("fleetctl"), "--config", kConfig, "security", "init", security, "--days", "2"}, 60);
  ASSERT_EQ(init.exit_code, 0) << init.err;
  const auto soak =
      run_command({bin("fleetctl"), "--domain", "111", "--config", kConfig, "--security", security, "soak", "--agents",
                   "2", "--vda5050-vehicles", "2", "--duration", "60", "--time-scale", "5", "--json"},
                  240);
  std::filesystem::remove_all(security);
  ASSERT_FALSE(soak.out.empty()) << soak.err;
  const json summary = last_json_line(soak.out);
  EXPECT_EQ(soak.exit_code, 0) << soak.err.substr(soak.err.size() > 3000 ? soak.err.size() - 3000 : 0);
  EXPECT_EQ(summary["collisions"], 0);
  EXPECT_EQ(summary["deadlocks"], 0);
  EXPECT_EQ(summary["orders_lost"], 0);
  EXPECT_GE(summary["orders_done_by_fleet"]["visitors"].get<int>(), 1) << summary.dump();
  EXPECT_GE(summary["orders_done_by_fleet"]["forklifts"].get<int>(), 1) << summary.dump();
  EXPECT_EQ(summary["refused_samples"], 0) << "every vehicle's reports come from its own partition";
}

TEST(Vda5050, AKilledVehicleIsLostItsOrderGoesBackAndItComesBackToFinishIt) {
  VdaFleet vda(112, 2);
  const std::size_t check = start_message_check(vda.fleet, mqtt_url_of(vda.vehicles.broker));
  ASSERT_TRUE(vda.fleet.wait_for_robots({"v1", "v2"}));
  const std::int64_t id = vda.order_under_way();
  ASSERT_NE(id, 0);

  vda.fleet.processes().signal(vda.vehicles_process, SIGKILL);  // the vehicles' process dies: no goodbye
  ASSERT_TRUE(wait_for_order(
      vda.fleet, id, [](const json& o) { return o.value("state", "") == "QUEUED" || o.value("state", "") == "FAILED"; },
      30))
      << order_of(vda.fleet, id).dump();
  EXPECT_EQ(order_of(vda.fleet, id)["state"], "QUEUED") << "given back, not failed: it carried nothing";
  const std::string bridge_log = slurp(vda.fleet.log_dir() + "/fleet-vda5050.log");
  EXPECT_NE(bridge_log.find("is lost: connection CONNECTIONBROKEN"), std::string::npos) << bridge_log;

  vda.fleet.processes().restart(vda.vehicles_process);  // back at their homes
  EXPECT_TRUE(wait_for_order(
      vda.fleet, id, [](const json& o) { return o.value("state", "") == "DONE"; }, 150))
      << order_of(vda.fleet, id).dump();

  const json checked = message_check_result(vda.fleet, check);
  EXPECT_GT(checked.value("checked", 0), 10) << checked.dump();
  EXPECT_EQ(checked.value("invalid_count", -1), 0) << checked.dump(2);
  if (std::filesystem::exists(fleet::test::source_dir() + "/../shared/data/vda5050")) {
    EXPECT_EQ(checked.value("schemas", ""), "official+lib");
  }
}

TEST(Vda5050, WhenTheBrokerDiesItsVehiclesAreLostAndComeBackWithTheirOrders) {
  VdaFleet vda(114, 1);
  ASSERT_TRUE(vda.fleet.wait_for_robots({"v1"}));
  const std::int64_t id = vda.order_under_way();
  ASSERT_NE(id, 0);

  const std::size_t broker = vda.process_named("mosquitto");
  ASSERT_LT(broker, vda.fleet.processes().children().size());
  vda.fleet.processes().signal(broker, SIGKILL);
  std::this_thread::sleep_for(std::chrono::seconds(3));
  vda.fleet.processes().restart(broker);  // the same port and configuration: the clients reconnect
  EXPECT_TRUE(wait_for_order(
      vda.fleet, id, [](const json& o) { return o.value("state", "") == "DONE"; }, 180))
      << order_of(vda.fleet, id).dump();
  const std::string bridge_log = slurp(vda.fleet.log_dir() + "/fleet-vda5050.log");
  EXPECT_NE(bridge_log.find("is lost: the MQTT broker is gone"), std::string::npos) << bridge_log;
  EXPECT_NE(bridge_log.find("is online again"), std::string::npos) << bridge_log;
}

TEST(Vda5050, AVehicleLostInPlaceIsToldItsHomeAndAnOrderItRefusesFailsWithItsReason) {
  // The vehicle also starts not knowing where it is: the master tells it its home (initPosition).
  VdaFleet vda(113, 1, {"--reject-orders", "agv-1", "--lost-position", "agv-1"});
  ASSERT_TRUE(vda.fleet.wait_for_robots({"v1"}));
  const std::string vehicles_log = vda.fleet.log_dir() + "/vda5050-vehicles-visitors.log";
  for (int i = 0; i < 100 && slurp(vehicles_log).find("position_initialized") == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  EXPECT_NE(slurp(vehicles_log).find("\"nodeId\":\"home-H5\""), std::string::npos) << slurp(vehicles_log);
  const auto added = vda.fleet.fleetctl(
      {"--json", "order", "add", "--from", "A5", "--to", "A2", "--fleet", "visitors", "--wait"}, 120);
  const json order = last_json_line(added.out);
  EXPECT_EQ(order["state"], "FAILED") << added.out << added.err;
  const std::string reason = order.value("reason", "");
  EXPECT_NE(reason.find("vehicle refused VDA 5050 order"), std::string::npos) << reason;
  EXPECT_NE(reason.find("orderError"), std::string::npos) << reason;
}
