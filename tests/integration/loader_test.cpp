// A loader job over real processes and DDS (domain 97): a picker walks a pick list and sets each
// box on the pallet of a stacker standing behind it; the full pallet goes to expedition and the
// second stacker moves up (docs/loader.md).

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "fleet_harness.hpp"
#include "test_paths.hpp"

using namespace fleet::testing;
using nlohmann::json;

TEST(Loader, APickerFillsTwoStackersPalletsAndBothGoToExpedition) {
  FleetHarness fleet(97, 10.0, "plant");
  fleet.use_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  fleet.start_server({"--set", "server.loader_pallet_boxes=3"});
  for (const char* robot : {"pk1", "st1", "st2"}) fleet.start_agent(robot);
  ASSERT_TRUE(fleet.wait_for_robots({"pk1", "st1", "st2"}));
  const std::string dir = ::testing::TempDir();
  // Four boxes: three fill the first pallet (RB1's two, one of RB3's), the fourth the second.
  std::ofstream(dir + "/loader.csv") << "place,item,quantity\nRB1,A1,2\nRB3,A3,2\n";

  const auto added = fleet.fleetctl(
      {"--json", "order", "add", "--kind", "pick", "--lines", dir + "/loader.csv", "--handling", "loader"}, 30);
  ASSERT_EQ(added.exit_code, 0) << added.err;
  const long pick = last_json_line(added.out)["order_id"].get<long>();

  const auto transports_of = [&](const json& orders) {
    std::vector<json> out;
    for (const auto& o : orders) {
      if (o["caused_by"] == json::array({pick})) out.push_back(o);
    }
    return out;
  };
  const json rows = orders_until(
      fleet,
      [&](const json& orders) {
        const auto transports = transports_of(orders);
        return transports.size() == 2 &&
               std::all_of(transports.begin(), transports.end(), [](const json& t) { return t["state"] == "DONE"; });
      },
      150);
  json picked;
  for (const auto& o : rows) {
    if (o["order_id"] == pick) picked = o;
  }
  ASSERT_EQ(picked["state"], "DONE") << rows.dump(1) << fleet.log_of("fleet-server");
  EXPECT_EQ(picked["robot_id"], "pk1");
  const auto transports = transports_of(rows);
  ASSERT_EQ(transports.size(), 2u) << rows.dump(1) << fleet.log_of("fleet-server");
  std::set<std::string> stackers;
  for (const auto& t : transports) {
    EXPECT_EQ(t["state"], "DONE") << t.dump(1) << fleet.log_of("fleet-server");
    EXPECT_EQ(t["drop_area"].get<std::string>().substr(0, 2), "EX") << t.dump(1);
    EXPECT_EQ(t["pick_area"].get<std::string>().substr(0, 2), "PK") << t.dump(1);
    stackers.insert(t["robot_id"].get<std::string>());
  }
  EXPECT_EQ(stackers, (std::set<std::string>{"st1", "st2"}));

  // The pick order names the transports that carried its boxes away.
  const auto shown = fleet.fleetctl({"order", "show", std::to_string(pick)}, 30);
  EXPECT_NE(shown.out.find("led to order " + std::to_string(transports[0]["order_id"].get<long>())), std::string::npos)
      << shown.out;
}

// The transporter behind the picker is killed once the first stop's boxes are on its pallet, and
// its agent comes back at its bay (the soak's fault): the job goes on with the other stacker
// from the first stop not done, on a new pallet; the two boxes on the lost pallet stay there,
// counted once, and the pick order ends with every box of its list loaded.
TEST(Loader, AStackerKilledMidJobIsReplacedAndTheJobEnds) {
  FleetHarness fleet(95, 10.0, "plant");
  fleet.use_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  fleet.start_server();
  const std::vector<std::string> robots{"pk1", "st1", "st2"};
  for (const auto& robot : robots) fleet.start_agent(robot);
  ASSERT_TRUE(fleet.wait_for_robots(robots));
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "/loader-kill.csv") << "place,item,quantity\nRB1,A1,2\nRB3,A3,2\n";
  const auto added = fleet.fleetctl(
      {"--json", "order", "add", "--kind", "pick", "--lines", dir + "/loader-kill.csv", "--handling", "loader"}, 30);
  ASSERT_EQ(added.exit_code, 0) << added.err;
  const long pick = last_json_line(added.out)["order_id"].get<long>();

  const auto find = [](const json& orders, long id) {
    for (const auto& o : orders) {
      if (o["order_id"] == id) return o;
    }
    return json();
  };
  // The first stop is done once the picker, having picked, drives on to the second.
  const auto first_stop_done = [&](const json& orders) {
    const json o = find(orders, pick);
    if (o.is_null()) return false;
    bool picked = false;
    for (const auto& e : o["history"]) {
      if (e["phase"] == "PICKING") picked = true;
      if (picked && e["phase"] == "TO_PICK") return true;
    }
    return false;
  };
  const json before = orders_until(fleet, first_stop_done, 150);
  ASSERT_TRUE(first_stop_done(before)) << before.dump(1) << fleet.log_of("fleet-server");
  std::string victim;
  long lost_transport = 0;
  for (const auto& o : before) {
    if (o["caused_by"] == json::array({pick}) && o["state"] == "ACTIVE") {
      victim = o["robot_id"].get<std::string>();
      lost_transport = o["order_id"].get<long>();
    }
  }
  ASSERT_FALSE(victim.empty()) << before.dump(1);
  const std::size_t index =
      1 + static_cast<std::size_t>(std::find(robots.begin(), robots.end(), victim) - robots.begin());
  fleet.processes().signal(index, SIGKILL);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  fleet.processes().reap();
  std::this_thread::sleep_for(std::chrono::seconds(2));
  fleet.processes().restart(index);

  const json after = orders_until(
      fleet,
      [&](const json& orders) {
        const json o = find(orders, pick);
        return !o.is_null() && (o["state"] == "DONE" || o["state"] == "FAILED") &&
               std::any_of(orders.begin(), orders.end(), [&](const json& t) {
                 return t["caused_by"] == json::array({pick}) && t["state"] == "DONE";
               });
      },
      240);
  const json picked = find(after, pick);
  ASSERT_EQ(picked["state"], "DONE") << after.dump(1) << fleet.log_of("fleet-server");
  EXPECT_EQ(find(after, lost_transport)["state"], "FAILED") << after.dump(1);
  int delivered = 0;
  for (const auto& t : after) {
    if (t["caused_by"] != json::array({pick}) || t["order_id"] == lost_transport) continue;
    EXPECT_EQ(t["state"], "DONE") << t.dump(1) << fleet.log_of("fleet-server");
    EXPECT_NE(t["robot_id"], victim) << "the other stacker took over";
    EXPECT_EQ(t["drop_area"].get<std::string>().substr(0, 2), "EX") << t.dump(1);
    ++delivered;
  }
  EXPECT_EQ(delivered, 1) << after.dump(1);
  // The lost pallet keeps the first stop's two boxes; the new one takes the second stop's alone.
  const std::string log = fleet.log_of("fleet-server");
  EXPECT_NE(log.find("deliver the pallet (2 boxes) to EX"), std::string::npos) << log;
  EXPECT_EQ(log.find("deliver the pallet (4 boxes)"), std::string::npos) << log;
}
