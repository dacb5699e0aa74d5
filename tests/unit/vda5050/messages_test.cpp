#include "vda5050/messages.hpp"

#include <gtest/gtest.h>

#include "vda5050/order_release.hpp"

namespace fleet::vda5050 {
namespace {

using nlohmann::json;

const VehicleAddress kVehicle{"uagv", "2.0.0", "Sim", "agv-7"};

TEST(Vda5050Messages, TopicsAndHeaderFollowTheSpecification) {
  EXPECT_EQ(topic(kVehicle, "order"), "uagv/v2/Sim/agv-7/order");
  const json h = header(kVehicle, 12, 1764907200.25);
  EXPECT_EQ(h["headerId"], 12);
  EXPECT_EQ(h["timestamp"], "2025-12-05T04:00:00.250Z");
  EXPECT_EQ(h["version"], "2.0.0");
  EXPECT_EQ(h["serialNumber"], "agv-7");
  EXPECT_EQ(iso_timestamp(1764907200.0004), "2025-12-05T04:00:00.000Z");
}

std::vector<OrderNode> line_of(int n) {
  std::vector<OrderNode> nodes;
  for (int i = 0; i < n; ++i) {
    std::string id = "p";
    id += std::to_string(i);
    nodes.push_back({id, 1.0 * i, 0.0, std::nullopt, {}});
  }
  nodes.back().actions.push_back({"pick", "o1-pick", "HARD", {{"loadType", "EPAL"}}});
  return nodes;
}

TEST(Vda5050Messages, AnOrderReleasesItsBaseAndStitchesEachUpdateAtTheBaseEnd) {
  ReleasedOrder order("o1-1", "table_a", "2.0.0", line_of(5), {0.0, 1.0, 2.0, 3.0, 4.0}, 0);
  const auto first = order.release(1.5);
  ASSERT_TRUE(first);
  const json j = order_json(*first);
  EXPECT_EQ(j["orderUpdateId"], 0);
  ASSERT_EQ(j["nodes"].size(), 5u);
  ASSERT_EQ(j["edges"].size(), 4u);
  for (std::size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(j["nodes"][k]["sequenceId"], 2 * k);
    EXPECT_EQ(j["nodes"][k]["released"], k <= 1) << k;
    EXPECT_EQ(j["nodes"][k]["nodePosition"]["mapId"], "table_a");
    EXPECT_TRUE(j["nodes"][k]["nodePosition"].contains("allowedDeviationXy")) << "2.0.0's schema spelling";
  }
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(j["edges"][k]["sequenceId"], 2 * k + 1);
    EXPECT_EQ(j["edges"][k]["released"], k + 1 <= 1) << k;
    EXPECT_EQ(j["edges"][k]["startNodeId"], j["nodes"][k]["nodeId"]);
  }
  EXPECT_EQ(j["nodes"][4]["actions"][0]["actionType"], "pick");

  EXPECT_FALSE(order.release(1.9)) << "no further node granted: nothing to send";
  const auto update = order.release(3.0);
  ASSERT_TRUE(update);
  const json u = order_json(*update);
  EXPECT_EQ(u["orderId"], "o1-1");
  EXPECT_EQ(u["orderUpdateId"], 1);
  EXPECT_EQ(u["nodes"][0]["nodeId"], "p1") << "stitched at the previous base's last node";
  EXPECT_EQ(u["nodes"][0]["sequenceId"], 2);
  EXPECT_EQ(u["nodes"][2]["released"], true);
  EXPECT_EQ(u["nodes"][3]["released"], false);
  EXPECT_FALSE(order.fully_released());
  ASSERT_TRUE(order.release(1e9));
  EXPECT_TRUE(order.fully_released());
}

TEST(Vda5050Messages, InstantActionsGoUnderBothKeys) {
  const json a = instant_action_json("cancelOrder", "c1", "2.0.0");
  EXPECT_EQ(a["actions"], a["instantActions"]);
  EXPECT_EQ(a["actions"][0]["actionName"], "cancelOrder") << "the 2.0.0 schema's name";
  EXPECT_FALSE(instant_action_json("cancelOrder", "c1", "2.1.0")["actions"][0].contains("actionName"));
  EXPECT_EQ(a["actions"][0]["actionType"], "cancelOrder");
  EXPECT_EQ(a["actions"][0]["blockingType"], "NONE");
}

json good_state() {
  return json::parse(R"({"headerId": 3, "timestamp": "2026-12-05T04:00:00.000Z", "version": "2.0.0",
    "manufacturer": "Sim", "serialNumber": "agv-7", "orderId": "o1-1", "orderUpdateId": 2,
    "lastNodeId": "p1", "lastNodeSequenceId": 2, "driving": true,
    "nodeStates": [{"nodeId": "p2", "sequenceId": 4, "released": true}], "edgeStates": [],
    "agvPosition": {"x": 1.5, "y": -0.25, "theta": 0.5, "mapId": "table_a", "positionInitialized": true},
    "velocity": {"vx": 0.3, "vy": 0.4},
    "actionStates": [{"actionId": "o1-pick", "actionType": "pick", "actionStatus": "WAITING"}],
    "batteryState": {"batteryCharge": 80, "charging": false}, "operatingMode": "AUTOMATIC",
    "errors": [{"errorType": "orderError", "errorLevel": "WARNING", "errorDescription": "bad stitch",
                "errorReferences": [{"referenceKey": "orderId", "referenceValue": "o1-1"}]}],
    "safetyState": {"eStop": "NONE", "fieldViolation": false}, "loads": []})");
}

TEST(Vda5050Messages, AStateIsReadWithItsProgressPositionActionsAndErrors) {
  const VehicleState s = parse_state(good_state());
  EXPECT_EQ(s.order_id, "o1-1");
  EXPECT_EQ(s.update_id, 2u);
  EXPECT_EQ(s.last_node_sequence_id, 2u);
  EXPECT_EQ(s.node_sequence_ids, std::vector<std::uint32_t>{4});
  EXPECT_TRUE(s.driving);
  EXPECT_TRUE(s.has_position);
  EXPECT_DOUBLE_EQ(s.y, -0.25);
  EXPECT_DOUBLE_EQ(s.speed, 0.5);
  ASSERT_EQ(s.actions.size(), 1u);
  EXPECT_EQ(s.actions[0].status, "WAITING");
  ASSERT_EQ(s.errors.size(), 1u);
  EXPECT_EQ(s.errors[0].references[0].second, "o1-1");
  EXPECT_FALSE(s.loaded);
}

TEST(Vda5050Messages, ABadStateNamesTheKey) {
  const auto reason = [](json message) {
    try {
      parse_state(message);
    } catch (const MessageError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  json missing = good_state();
  missing.erase("lastNodeId");
  EXPECT_EQ(reason(missing), "state: key 'lastNodeId' is missing");
  json wrong = good_state();
  wrong["agvPosition"]["x"] = "far";
  EXPECT_EQ(reason(wrong), "state.agvPosition: key 'x' must be a number, not \"far\"");
  json negative = good_state();
  negative["orderUpdateId"] = -1;
  EXPECT_EQ(reason(negative), "state: key 'orderUpdateId' must be a whole number >= 0, not -1");
  EXPECT_EQ(reason(json::array()), "state: not a JSON object");
  EXPECT_THROW(parse_connection(json{{"connectionState", "MAYBE"}}), MessageError);
  EXPECT_EQ(parse_connection(json{{"connectionState", "CONNECTIONBROKEN"}}), "CONNECTIONBROKEN");
}

TEST(Vda5050Messages, AFactsheetIsCheckedAgainstTheProfileFleetPlansWith) {
  const FactsheetFigures sheet =
      parse_factsheet(json::parse(R"({"physicalParameters": {"length": 1.2, "width": 0.8, "speedMax": 1.0}})"));
  EXPECT_TRUE(factsheet_differences(sheet, 1.2, 0.8, 1.0).empty());
  const auto off = factsheet_differences(sheet, 1.2, 0.6, 1.5);
  ASSERT_EQ(off.size(), 2u);
  EXPECT_EQ(off[0], "its factsheet says width 0.8 m, the fleet's profile 0.6 m");
  EXPECT_EQ(off[1], "its factsheet says speedMax 1 m/s, the fleet's profile 1.5 m/s");
  EXPECT_EQ(factsheet_differences(parse_factsheet(json::object()), 1, 1, 1),
            std::vector<std::string>{"its factsheet gives no physicalParameters"});
  EXPECT_THROW(parse_factsheet(json::parse(R"({"physicalParameters": {"length": -1}})")), MessageError);
}

}  // namespace
}  // namespace fleet::vda5050
