#include "vda5050/vehicle_master.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "map/site_map.hpp"
#include "test_paths.hpp"

namespace fleet::vda5050 {
namespace {

using geometry::Pose2;
using nlohmann::json;

const map::SiteMap& table_a() {
  static const map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/table_a.yaml"));
  return site;
}

/// A vehicle as VDA 5050 describes one, for the master to drive: it takes an order and its
/// updates (checking the stitch), drives its released nodes at `speed` and stops at the base's
/// end, runs each node's action for `action_steps` steps, and reports its state.
struct TestVehicle {
  double speed = 0.5;  ///< metres a step
  int action_steps = 3;
  std::string order_id;
  std::uint32_t update_id = 0;
  std::vector<json> nodes;  ///< the order's nodes not yet passed, the last passed first
  std::string last_node_id;
  std::uint32_t last_sequence = 0;
  double x = 0.0, y = 0.0, theta = 0.0;
  bool driving = false;
  std::map<std::string, std::string> action_status;  ///< action id -> status
  std::map<std::string, std::string> action_type;
  int action_left = 0;
  std::vector<std::string> stitch_errors;
  std::vector<std::string> rejected;  ///< order ids this vehicle refuses

  void take(const json& order) {
    const std::string id = order["orderId"];
    if (std::find(rejected.begin(), rejected.end(), id) != rejected.end()) {
      error_for = id;
      return;
    }
    if (id == order_id) {
      if (order["orderUpdateId"].get<std::uint32_t>() <= update_id) stitch_errors.push_back("update id not raised");
      const json& first = order["nodes"][0];
      // The update starts at the base's last node: the last released one the vehicle knows.
      std::size_t base_end = 0;
      while (base_end + 1 < nodes.size() && nodes[base_end + 1]["released"].get<bool>()) ++base_end;
      if (first["sequenceId"] != nodes[base_end]["sequenceId"] || first["nodeId"] != nodes[base_end]["nodeId"]) {
        stitch_errors.push_back("update stitched at " + first["nodeId"].get<std::string>());
      }
      nodes.resize(base_end);
      for (const json& n : order["nodes"]) nodes.push_back(n);
    } else {
      // Still in an order (a horizon left): a new order must start where the base ends.
      if (nodes.size() > 1 && (order["nodes"][0]["nodeId"] != nodes[0]["nodeId"] ||
                               order["nodes"][0]["sequenceId"] != nodes[0]["sequenceId"])) {
        stitch_errors.push_back("a new order does not start at the active order's base end");
      }
      nodes.clear();
      for (const json& n : order["nodes"]) nodes.push_back(n);
      const json& p = nodes.front()["nodePosition"];
      if (std::hypot(p["x"].get<double>() - x, p["y"].get<double>() - y) > 0.3) {
        stitch_errors.push_back("a new order starts away from the vehicle");
      }
      last_node_id = nodes.front()["nodeId"];
      last_sequence = nodes.front()["sequenceId"];
    }
    order_id = id;
    update_id = order["orderUpdateId"];
    for (const json& n : order["nodes"]) {
      for (const json& a : n["actions"]) {
        action_status.emplace(a["actionId"], "WAITING");
        action_type[a["actionId"]] = a["actionType"];
      }
    }
  }

  void step() {
    driving = false;
    if (action_left > 0) {
      if (--action_left == 0) {
        for (auto& [id, status] : action_status) {
          if (status == "RUNNING") status = "FINISHED";
        }
      }
      return;
    }
    if (nodes.size() < 2 || !nodes[1]["released"].get<bool>()) return;
    const json& p = nodes[1]["nodePosition"];
    const double dx = p["x"].get<double>() - x, dy = p["y"].get<double>() - y;
    const double d = std::hypot(dx, dy);
    driving = true;
    if (d > speed) {
      x += dx / d * speed;
      y += dy / d * speed;
      theta = std::atan2(dy, dx);
      return;
    }
    x = p["x"];
    y = p["y"];
    nodes.erase(nodes.begin());
    last_node_id = nodes.front()["nodeId"];
    last_sequence = nodes.front()["sequenceId"];
    for (const json& a : nodes.front()["actions"]) {
      action_status[a["actionId"]] = "RUNNING";
      action_left = action_steps;
    }
  }

  std::string error_for;

  VehicleState state() const {
    VehicleState s;
    s.order_id = order_id;
    s.update_id = update_id;
    s.last_node_id = last_node_id;
    s.last_node_sequence_id = last_sequence;
    for (std::size_t k = 1; k < nodes.size(); ++k) {
      s.node_sequence_ids.push_back(nodes[k]["sequenceId"]);
      if (nodes[k]["released"].get<bool>()) ++s.released_nodes_left;
    }
    s.driving = driving;
    s.has_position = true;
    s.x = x;
    s.y = y;
    s.theta = theta;
    for (const auto& [id, status] : action_status) s.actions.push_back({id, action_type.at(id), status, ""});
    if (!error_for.empty()) {
      s.errors.push_back({"orderError", "WARNING", "cannot reach the first node", {{"orderId", error_for}}});
    }
    return s;
  }
};

/// The master of one test vehicle at H1 of table_a, and a stand-in for traffic control that
/// grants each route up to `granted` metres from its first point.
struct Yard {
  std::shared_ptr<const map::RoadGraph> graph = std::make_shared<map::RoadGraph>(table_a().graph.graph);
  emulation::EmulatedRoutes routes{graph};
  const Pose2 home = table_a().site.find_home("H1")->pose;
  VehicleMaster master{"v1", "2.0.0", "table_a", "H1", home, 1000};
  TestVehicle vehicle;
  std::vector<MasterEvent> events;
  std::vector<json> orders;
  double granted = 1e9;
  /// Every order message: no node released past the grant of its route.
  std::vector<std::string> released_past_grant;

  Yard() {
    vehicle.x = home.x;
    vehicle.y = home.y;
  }

  double grant_route() {
    const robot::TrafficRoute route = master.traffic_route();
    if (route.points.empty()) return 1e9;
    robot::TrafficPermit permit;
    permit.version = route.version;
    double along = 0.0;
    for (std::size_t i = 1; i < route.points.size(); ++i) {
      const auto& a = graph->points[static_cast<std::size_t>(route.points[i - 1])];
      const auto& b = graph->points[static_cast<std::size_t>(route.points[i])];
      along += std::hypot(b.x - a.x, b.y - a.y);
      if (along > granted + 1e-9) break;
      permit.granted_index = static_cast<int>(i);
      permit.granted_distance = along;
    }
    master.grant(permit);
    return permit.granted_distance;
  }

  void step() {
    master.take_state(vehicle.state());
    const robot::TrafficRoute route = master.traffic_route();
    grant_route();
    master.step(routes);
    for (Outgoing& out : master.take_messages()) {
      if (out.name != "order") continue;
      check_released_within_grant(out.body, route);
      orders.push_back(out.body);
      vehicle.take(out.body);
    }
    for (auto& e : master.take_events()) events.push_back(e);
    vehicle.step();
  }

  /// Every released road node lies on the route within the grant.
  void check_released_within_grant(const json& order, const robot::TrafficRoute& route) {
    for (const json& n : order["nodes"]) {
      const std::string id = n["nodeId"];
      if (!n["released"].get<bool>() || id.empty() || id[0] != 'p' || route.points.empty()) continue;
      const int point = std::stoi(id.substr(1));
      double along = 0.0;
      for (std::size_t i = 0; i < route.points.size(); ++i) {
        if (i > 0) {
          const auto& a = graph->points[static_cast<std::size_t>(route.points[i - 1])];
          const auto& b = graph->points[static_cast<std::size_t>(route.points[i])];
          along += std::hypot(b.x - a.x, b.y - a.y);
        }
        if (route.points[i] == point && along > granted + 1e-6) released_past_grant.push_back(id);
      }
    }
  }

  std::vector<std::string> phases() const {
    std::vector<std::string> out;
    for (const auto& e : events) {
      out.push_back(e.kind == MasterEvent::Kind::kPhase  ? e.phase
                    : e.kind == MasterEvent::Kind::kDone ? "DONE"
                                                         : "FAILED");
    }
    return out;
  }
};

MasterOrder transport(const std::string& from, const std::string& to) {
  const map::Site& site = table_a().site;
  return {7, orders::OrderKind::kTransport, from, site.find_area(from)->pose, to, site.find_area(to)->pose, 42};
}

TEST(VehicleMaster, ReleasesOnlyWhatTrafficGrantsAndRunsATransportToItsEnd) {
  Yard yard;
  yard.vehicle.speed = 0.05;
  yard.granted = 0.4;
  ASSERT_EQ(yard.master.submit(transport("A5", "A1")), "");
  for (int i = 0; i < 200; ++i) yard.step();
  ASSERT_FALSE(yard.orders.empty());
  EXPECT_TRUE(yard.released_past_grant.empty()) << yard.released_past_grant.front();
  EXPECT_FALSE(yard.orders.front()["nodes"].back()["released"].get<bool>()) << "the goal is horizon at first";
  EXPECT_EQ(yard.phases(), std::vector<std::string>{"TO_PICK"}) << "held at the grant's end";
  const std::size_t updates_before = yard.orders.size();

  yard.granted = 1e9;
  for (int i = 0; i < 3000 && yard.master.order(); ++i) yard.step();
  EXPECT_GT(yard.orders.size(), updates_before);
  EXPECT_TRUE(yard.vehicle.stitch_errors.empty()) << yard.vehicle.stitch_errors.front();
  EXPECT_EQ(yard.phases(), (std::vector<std::string>{"TO_PICK", "PICKING", "TO_DROP", "DROPPING", "DONE"}));
  ASSERT_EQ(yard.events.back().kind, MasterEvent::Kind::kDone);
  EXPECT_EQ(yard.events.back().load_id, 42);
  bool picked_with_load = false;
  for (const json& o : yard.orders) {
    for (const json& n : o["nodes"]) {
      for (const json& a : n["actions"]) {
        if (a["actionType"] == "pick" && n["nodeId"] == "A5") {
          picked_with_load = a["actionParameters"].dump().find("\"42\"") != std::string::npos;
        }
      }
    }
  }
  EXPECT_TRUE(picked_with_load) << "the pick at A5 names the load";

  // Home again: the vehicle ends where it started, with no order.
  for (int i = 0; i < 3000 && yard.master.task_state() != "IDLE"; ++i) yard.step();
  EXPECT_EQ(yard.master.task_state(), "IDLE");
  EXPECT_NEAR(yard.vehicle.x, yard.home.x, 1e-6);
  EXPECT_NEAR(yard.vehicle.y, yard.home.y, 1e-6);
}

TEST(VehicleMaster, AnOrderTheVehicleRefusesFailsWithItsReason) {
  Yard yard;
  ASSERT_EQ(yard.master.submit(transport("A5", "A1")), "");
  yard.step();  // plans and asks traffic
  yard.step();  // granted: the first order goes out
  ASSERT_EQ(yard.orders.size(), 1u);
  yard.vehicle.rejected.push_back(yard.orders.front()["orderId"]);
  yard.vehicle.error_for = yard.orders.front()["orderId"];
  for (int i = 0; i < 5; ++i) yard.step();
  ASSERT_EQ(yard.phases(), (std::vector<std::string>{"TO_PICK", "FAILED"}));
  EXPECT_NE(yard.events.back().reason.find("orderError (cannot reach the first node)"), std::string::npos)
      << yard.events.back().reason;
  EXPECT_FALSE(yard.master.order());
}

TEST(VehicleMaster, ACancelledOrderIsCancelledOnTheVehicleOnce) {
  Yard yard;
  yard.granted = 0.4;
  ASSERT_EQ(yard.master.submit(transport("A5", "A1")), "");
  for (int i = 0; i < 20; ++i) yard.step();
  EXPECT_TRUE(yard.master.withdraw());
  std::vector<Outgoing> sent = yard.master.take_messages();
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].name, "instantActions");
  EXPECT_EQ(sent[0].body["actions"][0]["actionType"], "cancelOrder");
  yard.vehicle.nodes.resize(1);  // the vehicle drops its order, as cancelOrder asks
  for (int i = 0; i < 10; ++i) yard.step();
  for (const Outgoing& o : yard.master.take_messages()) EXPECT_NE(o.name, "instantActions") << "sent once";
  ASSERT_FALSE(yard.orders.empty());
  EXPECT_EQ(yard.orders.back()["nodes"].back()["nodeId"], "home-H1") << "on its way home";
}

TEST(VehicleMaster, AVehicleBackFromBeingLostTakesTheOrderAgainStitchedWhereItWaits) {
  Yard yard;
  yard.vehicle.speed = 0.05;
  yard.granted = 0.4;
  ASSERT_EQ(yard.master.submit(transport("A5", "A1")), "");
  for (int i = 0; i < 200; ++i) yard.step();  // waits at the end of its base, with a horizon
  ASSERT_FALSE(yard.vehicle.nodes.size() < 2) << "a horizon is left";
  // Lost: the server withdraws the order (the cancel never reaches the vehicle) and gives it back.
  EXPECT_TRUE(yard.master.withdraw());
  yard.master.reconnected();
  ASSERT_EQ(yard.master.submit(transport("A5", "A1")), "");
  yard.granted = 1e9;
  for (int i = 0; i < 3000 && yard.master.order(); ++i) yard.step();
  EXPECT_TRUE(yard.vehicle.stitch_errors.empty()) << yard.vehicle.stitch_errors.front();
  ASSERT_FALSE(yard.events.empty());
  EXPECT_EQ(yard.events.back().kind, MasterEvent::Kind::kDone) << yard.phases().back();
}

TEST(VehicleMaster, PauseAndResumeAreSentOnceEachAndAgainToAVehicleThatCameBack) {
  Yard yard;
  const auto instant_actions = [&] {
    std::vector<std::string> types;
    for (const Outgoing& o : yard.master.take_messages()) {
      if (o.name == "instantActions") types.push_back(o.body["actions"][0]["actionType"]);
    }
    return types;
  };
  yard.master.set_paused(true);
  yard.master.set_paused(true);
  EXPECT_EQ(instant_actions(), std::vector<std::string>{"startPause"});
  yard.master.reconnected();
  EXPECT_EQ(instant_actions(), std::vector<std::string>{"startPause"}) << "a restarted vehicle is told again";
  yard.master.set_paused(false);
  EXPECT_EQ(instant_actions(), std::vector<std::string>{"stopPause"});
}

TEST(VehicleMaster, AVehicleThatDoesNotKnowWhereItIsIsToldItsHomeOnce) {
  Yard yard;
  const json state = {
      {"headerId", 1},
      {"orderId", ""},
      {"orderUpdateId", 0},
      {"lastNodeId", ""},
      {"lastNodeSequenceId", 0},
      {"nodeStates", json::array()},
      {"edgeStates", json::array()},
      {"actionStates", json::array()},
      {"driving", false},
      {"errors", json::array()},
      {"agvPosition", {{"x", 0.0}, {"y", 0.0}, {"theta", 0.0}, {"mapId", "table_a"}, {"positionInitialized", false}}}};
  const auto init_positions = [&] {
    std::vector<json> sent;
    for (const Outgoing& o : yard.master.take_messages()) {
      if (o.name == "instantActions" && o.body["actions"][0]["actionType"] == "initPosition") sent.push_back(o.body);
    }
    return sent;
  };
  yard.master.take_state(parse_state(state));
  const std::vector<json> sent = init_positions();
  ASSERT_EQ(sent.size(), 1u);
  std::map<std::string, json> parameters;
  for (const json& p : sent[0]["actions"][0]["actionParameters"]) parameters[p["key"]] = p["value"];
  EXPECT_DOUBLE_EQ(parameters["x"].get<double>(), yard.home.x);
  EXPECT_DOUBLE_EQ(parameters["theta"].get<double>(), yard.home.yaw);
  EXPECT_EQ(parameters["lastNodeId"], "home-H1");
  EXPECT_EQ(yard.master.pose().x, yard.home.x) << "an uninitialised position is not taken";
  yard.master.take_state(parse_state(state));
  EXPECT_TRUE(init_positions().empty()) << "told once";
  json known = state;
  known["agvPosition"]["positionInitialized"] = true;
  yard.master.take_state(parse_state(known));
  yard.master.take_state(parse_state(state));
  EXPECT_EQ(init_positions().size(), 1u) << "lost again, told again";
}

}  // namespace
}  // namespace fleet::vda5050
