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
