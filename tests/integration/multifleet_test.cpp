// Two fleets of different vehicles under one server: typed orders and dispatch by capability over
// real processes and DDS (domains 93-94).

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <thread>

#include "fleet_harness.hpp"
#include "test_paths.hpp"

using namespace fleet::testing;
using nlohmann::json;

namespace {

/// forklifts (fl1) pick and drop; movers (fa1, first by id) only drive: a transport must go to
/// fl1 although every policy would prefer fa1 otherwise.
std::string two_fleet_config(int domain) {
  const std::string path = ::testing::TempDir() + "/fleet-two-fleets-" + std::to_string(domain) + ".yaml";
  std::ofstream(path) << R"(site: table_a
fleets:
  - id: forklifts
    robot_type: forklift
    robots: [{id: fl1, home: H1}]
  - id: movers
    robot_type: forklift
    profile:
      footprint: [[0.12, -0.07], [0.12, 0.07], [-0.10, 0.07], [-0.12, 0.0], [-0.10, -0.07]]
      actions: []
    robots: [{id: fa1, home: H2}]
)";
  return path;
}

}  // namespace

TEST(MultiFleet, OrdersGoToFleetsThatCanDoThemAndOthersAreBadInput) {
  FleetHarness fleet(93, 10.0);
  fleet.use_config(two_fleet_config(93));
  fleet.start_server();
  fleet.start_agent("fl1");
  fleet.start_agent("fa1");
  ASSERT_TRUE(fleet.wait_for_robots({"fl1", "fa1"}));

  const auto fleets = fleet.fleetctl({"--json", "fleets"}, 30);
  ASSERT_EQ(fleets.exit_code, 0) << fleets.err;
  const json sheets = last_json_line(fleets.out)["fleets"];
  ASSERT_EQ(sheets.size(), 2u);
  EXPECT_EQ(sheets[1]["agvGeometry"]["envelopes2d"][0]["polyPoints"].size(), 5u);
  EXPECT_TRUE(sheets[1]["protocolFeatures"]["agvActions"].empty());

  // No fleet on the site performs pickItem: bad input, nothing stored.
  const auto pick = fleet.fleetctl({"order", "add", "--kind", "pick", "--from", "A1", "--to", "A2"}, 30);
  EXPECT_EQ(pick.exit_code, 2) << pick.err;
  EXPECT_NE(pick.err.find("forklifts cannot 'pickItem'"), std::string::npos) << pick.err;
  EXPECT_NE(pick.err.find("movers cannot 'pickItem'"), std::string::npos) << pick.err;
  const auto pinned = fleet.fleetctl({"order", "add", "--from", "A1", "--to", "A2", "--fleet", "movers"}, 30);
  EXPECT_EQ(pinned.exit_code, 2) << pinned.err;
  EXPECT_NE(pinned.err.find("movers cannot 'pick'"), std::string::npos) << pinned.err;
  const auto none = fleet.fleetctl({"--json", "order", "list"}, 30);
  ASSERT_EQ(none.exit_code, 0) << none.err;
  EXPECT_TRUE(last_json_line(none.out).empty()) << none.out;

  // A transport goes to the only fleet that picks and drops.
  const auto transport = fleet.fleetctl({"--json", "order", "add", "--from", "A1", "--to", "A2", "--wait"}, 240);
  ASSERT_EQ(transport.exit_code, 0) << transport.err;
  const json done = last_json_line(transport.out);
  EXPECT_EQ(done["robot_id"], "fl1") << transport.out;
  EXPECT_EQ(done["kind"], "transport");

  // A move: the mover drives to a free parking place and stays there.
  const auto move = fleet.fleetctl({"--json", "order", "add", "--kind", "move", "--to", "H7", "--wait"}, 240);
  ASSERT_EQ(move.exit_code, 0) << move.err;
  const json moved = last_json_line(move.out);
  EXPECT_EQ(moved["kind"], "move");
  EXPECT_EQ(moved["steps"][0]["place"], "H7");
  EXPECT_TRUE(moved["step"].is_null());  // done: in no phase, so in no step
  const std::string mover = moved["robot_id"];
  const auto robots = fleet.fleetctl({"--json", "robots"}, 30);
  ASSERT_EQ(robots.exit_code, 0) << robots.err;
  bool parked = false;
  for (const auto& r : last_json_line(robots.out)) {
    // H7 of table_a stands at (1.88, 2.18).
    if (r["robot_id"] == mover) parked = std::hypot(r["x"].get<double>() - 1.88, r["y"].get<double>() - 2.18) < 0.1;
  }
  EXPECT_TRUE(parked) << robots.out;
  // Its place is taken now; a move there is refused by the fleet (exit 1), not bad input.
  const auto taken = fleet.fleetctl({"order", "add", "--kind", "move", "--to", "H7"}, 30);
  EXPECT_EQ(taken.exit_code, 1) << taken.err;
  EXPECT_NE(taken.err.find("parking place 'H7' is " + mover + "'s"), std::string::npos) << taken.err;
}

// A pick list on the plant: a picker drives the tour over real processes and DDS (domain 94),
// and lines the places cannot give are refused before anything is stored.
TEST(MultiFleet, APickerDrivesAPickListsTourAndBadLinesAreNamed) {
  FleetHarness fleet(94, 10.0, "plant");
  fleet.use_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  fleet.start_server();
  fleet.start_agent("pk1");
  ASSERT_TRUE(fleet.wait_for_robots({"pk1"}));
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "/tour.csv") << "place,item,quantity\nRB1,A1,1\nRB3,A3,1\n";
  std::ofstream(dir + "/heavy.csv") << "RB1,A1,1\nRB4,A4,1\n";
  std::ofstream(dir + "/too_many.csv") << "RB1,A1,6\n";

  const auto heavy =
      fleet.fleetctl({"order", "add", "--kind", "pick", "--lines", dir + "/heavy.csv", "--to", "PS1"}, 30);
  EXPECT_EQ(heavy.exit_code, 2) << heavy.err;
  EXPECT_NE(heavy.err.find("heavy.csv:2: a box of A4 weighs 12.0 kg"), std::string::npos) << heavy.err;

  const auto tour = fleet.fleetctl(
      {"--json", "order", "add", "--kind", "pick", "--lines", dir + "/tour.csv", "--to", "PS1", "--wait"}, 300);
  ASSERT_EQ(tour.exit_code, 0) << tour.err << fleet.log_of("fleet-agent-pk1");
  const json done = last_json_line(tour.out);
  EXPECT_EQ(done["kind"], "pick");
  EXPECT_EQ(done["robot_id"], "pk1");
  EXPECT_EQ(done["state"], "DONE");

  // RB1 had 6 boxes of A1 and the tour took one: 6 more are more than it has left. The line is
  // good input; the place's stock is the fleet's state (exit 1).
  const auto more =
      fleet.fleetctl({"order", "add", "--kind", "pick", "--lines", dir + "/too_many.csv", "--to", "PS1"}, 30);
  EXPECT_EQ(more.exit_code, 1) << more.err;
  EXPECT_NE(more.err.find("pick list:1: place RB1 holds 5 boxes of A1, the lines ask for 6"), std::string::npos)
      << more.err;
}

TEST(MultiFleet, APickerFillsAPackingPalletAndAStackerTakesItToExpeditionAndBringsAnEmptyOne) {
  // The plant's packing pallets take 4 boxes: two 2-box tours fill PS9's, on the south cross aisle.
  // The server then orders the full pallet to a free expedition place and an empty one from the
  // packaging corridor to PS9, and the stacker, docking from the aisle, drives both [Picker thesis,
  // section 4.3.3.1: pickers load, transporters carry]. A tour asked for meanwhile goes on to PS10.
  FleetHarness fleet(95, 10.0, "plant");
  fleet.use_config(fleet::test::source_dir() + "/config/sites/plant.yaml");
  fleet.start_server();
  for (const char* robot : {"pk1", "st1"}) fleet.start_agent(robot);
  ASSERT_TRUE(fleet.wait_for_robots({"pk1", "st1"}));
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "/fill.csv") << "place,item,quantity\nRB1,A1,2\nRB3,A3,2\n";
  std::ofstream(dir + "/one.csv") << "RB2,A2,1\n";

  const auto fill =
      fleet.fleetctl({"--json", "order", "add", "--kind", "pick", "--lines", dir + "/fill.csv", "--to", "PS9"}, 30);
  ASSERT_EQ(fill.exit_code, 0) << fill.err;
  const json tours = last_json_line(fill.out)["order_ids"];
  ASSERT_EQ(tours.size(), 2u) << fill.out;
  const auto one =
      fleet.fleetctl({"--json", "order", "add", "--kind", "pick", "--lines", dir + "/one.csv", "--to", "PS9"}, 30);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const auto moved_on =
      fleet.fleetctl({"--json", "order", "show", std::to_string(last_json_line(one.out)["order_id"].get<long>())}, 30);
  EXPECT_EQ(last_json_line(moved_on.out)["drop_area"], "PS10") << "PS9's pallet is promised 4 boxes already";

  // Both tours done, then both transports of the chain.
  const json rows = orders_until(
      fleet,
      [](const json& orders) {
        int chain_done = 0;
        for (const auto& o : orders) chain_done += !o["cause"].get<std::string>().empty() && o["state"] == "DONE";
        return chain_done == 2;
      },
      240);
  const json* full = nullptr;
  const json* empty = nullptr;
  for (const auto& o : rows) {
    if (o["cause"].get<std::string>().empty()) continue;
    (o["pick_area"] == "PS9" ? full : empty) = &o;
  }
  ASSERT_TRUE(full && empty) << rows.dump(1) << fleet.log_of("fleet-server");
  EXPECT_EQ((*full)["state"], "DONE") << (*full)["reason"];
  EXPECT_EQ((*full)["drop_area"], "EX1") << "the first free expedition place";
  EXPECT_EQ((*full)["robot_id"], "st1");
  EXPECT_EQ((*empty)["robot_id"], "st1");
  EXPECT_EQ((*full)["caused_by"], tours);
  EXPECT_EQ((*empty)["drop_area"], "PS9");
  EXPECT_EQ((*empty)["state"], "DONE") << (*empty)["reason"];
  EXPECT_EQ((*empty)["caused_by"], json::array({(*full)["order_id"]}));

  // order show names the chain both ways.
  const auto tour = fleet.fleetctl({"order", "show", std::to_string(tours[0].get<long>())}, 30);
  EXPECT_NE(tour.out.find("led to order " + std::to_string((*full)["order_id"].get<long>()) + ": PS9 -> EX1"),
            std::string::npos)
      << tour.out;
  const auto taken = fleet.fleetctl({"order", "show", std::to_string((*full)["order_id"].get<long>())}, 30);
  EXPECT_NE(taken.out.find("because the pallet at PS9 is full: 4 boxes from orders"), std::string::npos) << taken.out;
}
