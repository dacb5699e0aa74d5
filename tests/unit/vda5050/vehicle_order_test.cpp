#include "vda5050/vehicle_order.hpp"

#include <gtest/gtest.h>

#include "map/site_map.hpp"
#include "test_paths.hpp"
#include "vda5050/vehicle_drive.hpp"

namespace fleet::vda5050 {
namespace {

using nlohmann::json;

const map::SiteMap& table_a() {
  static const map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/table_a.yaml"));
  return site;
}

json action(const std::string& id, const std::string& type) {
  return {{"actionId", id}, {"actionType", type}, {"blockingType", "HARD"}, {"actionParameters", json::array()}};
}

/// An order over `node_ids` starting at `first_sequence`, released up to `released` nodes;
/// `actions[k]` on node k.
json order(const std::string& id, std::uint32_t update, const std::vector<std::string>& node_ids,
           std::uint32_t first_sequence = 0, std::size_t released = 100,
           const std::map<std::size_t, json>& actions = {}) {
  json nodes = json::array();
  json edges = json::array();
  for (std::size_t k = 0; k < node_ids.size(); ++k) {
    json node = {{"nodeId", node_ids[k]},
                 {"sequenceId", first_sequence + 2 * k},
                 {"released", k < released},
                 {"actions", json::array()}};
    if (const auto a = actions.find(k); a != actions.end()) node["actions"].push_back(a->second);
    nodes.push_back(node);
    if (k > 0) {
      edges.push_back({{"edgeId", node_ids[k - 1] + "-" + node_ids[k]},
                       {"sequenceId", first_sequence + 2 * k - 1},
                       {"released", k < released},
                       {"startNodeId", node_ids[k - 1]},
                       {"endNodeId", node_ids[k]},
                       {"actions", json::array()}});
    }
  }
  return {{"headerId", 7}, {"orderId", id}, {"orderUpdateId", update}, {"nodes", nodes}, {"edges", edges}};
}

OrderVerdict receive(VehicleOrder& vehicle, const json& message, bool at_first_node = true) {
  const ReceivedOrder received = read_order(message);
  OrderVerdict verdict = vehicle.check(received, message, at_first_node);
  if (verdict.intake) vehicle.take(received, *verdict.intake);
  return verdict;
}

TEST(VehicleOrderTest, ReadOrderNamesWhatBreaksTheGraph) {
  json bad = order("o1", 0, {"H1", "p1", "p2"});
  bad["edges"][1]["startNodeId"] = "p9";
  EXPECT_THROW(
      {
        try {
          read_order(bad);
        } catch (const MessageError& e) {
          EXPECT_NE(std::string(e.what()).find("edges[1]"), std::string::npos) << e.what();
          throw;
        }
      },
      MessageError);
  bad = order("o1", 0, {"H1", "p1"});
  bad["nodes"][1]["sequenceId"] = 3;
  EXPECT_THROW(read_order(bad), MessageError);
  bad = order("o1", 0, {"H1", "p1", "p2"}, 0, 1);
  bad["nodes"][2]["released"] = true;
  bad["edges"][1]["released"] = true;
  EXPECT_THROW(read_order(bad), MessageError);  // released after the horizon began
  bad = order("o1", 0, {"H1", "A1"}, 0, 100, {{1, action("a", "pick")}});
  bad["nodes"][1]["actions"].push_back(action("a", "drop"));
  EXPECT_THROW(read_order(bad), MessageError);  // one action id twice
  EXPECT_THROW(read_order(json::array()), MessageError);
}

TEST(VehicleOrderTest, NewOrderThenUpdatesStitchedAtTheBaseEnd) {
  VehicleOrder vehicle;
  EXPECT_FALSE(vehicle.cancel());  // no order: noOrderToCancel
  auto verdict = receive(vehicle, order("o1", 0, {"H1", "p1", "p2", "p3"}, 0, 2), false);
  ASSERT_TRUE(verdict.error);
  EXPECT_EQ(verdict.error->type, "noRouteError");

  verdict = receive(vehicle, order("o1", 0, {"H1", "p1", "p2", "p3"}, 0, 2));
  ASSERT_EQ(verdict.intake, OrderIntake::kNew);
  EXPECT_EQ(vehicle.last_node_id(), "H1");
  EXPECT_EQ(vehicle.base_end().id, "p1");
  EXPECT_EQ(vehicle.node_states().size(), 3u);

  // The same update again changes nothing; a lower one is an orderUpdateError.
  EXPECT_EQ(receive(vehicle, order("o1", 0, {"H1", "p1"})).intake, OrderIntake::kRepeat);
  EXPECT_EQ(receive(vehicle, order("o1", 2, {"p1", "p2", "p3"}, 2, 1)).intake, OrderIntake::kStitch);
  verdict = receive(vehicle, order("o1", 1, {"p1", "p2"}, 2));
  ASSERT_TRUE(verdict.error);
  EXPECT_EQ(verdict.error->type, "orderUpdateError");

  // An update that does not begin at the base end (p1, sequence 2) is refused and names its node.
  verdict = receive(vehicle, order("o1", 3, {"p2", "p3"}, 4));
  ASSERT_TRUE(verdict.error);
  EXPECT_EQ(verdict.error->type, "orderUpdateError");
  EXPECT_NE(verdict.error->description.find("sequenceId 2"), std::string::npos) << verdict.error->description;

  verdict = receive(vehicle, order("o1", 3, {"p1", "p2", "p3"}, 2, 3));
  EXPECT_EQ(verdict.intake, OrderIntake::kStitch);
  EXPECT_EQ(vehicle.base_end().id, "p3");
  vehicle.passed(4);
  EXPECT_EQ(vehicle.last_node_id(), "p2");
  EXPECT_EQ(vehicle.edge_states().size(), 1u);
  vehicle.passed(6);
  EXPECT_FALSE(vehicle.active());
  // Standing at its base end, a new order may begin there.
  verdict = receive(vehicle, order("o2", 0, {"p3", "p4"}, 6), false);
  EXPECT_EQ(verdict.intake, OrderIntake::kNew);
}

TEST(VehicleOrderTest, ANewOrderWhileOneIsActiveMustStitch) {
  VehicleOrder vehicle;
  receive(vehicle, order("o1", 0, {"H1", "p1", "p2"}, 0, 3));
  auto verdict = receive(vehicle, order("o2", 0, {"H1", "p5"}));
  ASSERT_TRUE(verdict.error);
  EXPECT_EQ(verdict.error->type, "orderUpdateError");
  verdict = receive(vehicle, order("o2", 0, {"p2", "p5"}, 4));
  EXPECT_EQ(verdict.intake, OrderIntake::kStitch);
  EXPECT_EQ(vehicle.order_id(), "o2");
}

TEST(VehicleOrderTest, CancelFailsWhatIsNotEnded) {
  VehicleOrder vehicle;
  receive(vehicle, order("o1", 0, {"H1", "A1", "A2"}, 0, 100, {{1, action("a1", "pick")}, {2, action("a2", "drop")}}));
  vehicle.set_action_status("a1", "FINISHED");
  ASSERT_TRUE(vehicle.cancel());
  const json states = vehicle.action_states_json();
  EXPECT_EQ(states[0]["actionStatus"], "FINISHED");
  EXPECT_EQ(states[1]["actionStatus"], "FAILED");
  EXPECT_FALSE(vehicle.cancel());
}

TEST(VehicleDriveTest, JobsOfTransportsAndMovesAndWhatRejectsThem) {
  const auto& site = table_a();
  const auto nodes_of = [](const json& message) {
    const ReceivedOrder o = read_order(message);
    return std::vector<ReceivedNode>(o.nodes.begin() + 1, o.nodes.end());
  };
  json m = order("o1", 0, {"H1", "A1", "A2"}, 0, 100, {{1, action("a1", "pick")}, {2, action("a2", "drop")}});
  auto job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleJob>(job));
  EXPECT_EQ(std::get<VehicleJob>(job).order.kind, orders::OrderKind::kTransport);
  EXPECT_EQ(std::get<VehicleJob>(job).order.pick_area_id, "A1");
  EXPECT_EQ(std::get<VehicleJob>(job).goal_node, 4u);

  job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, false, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleError>(job));
  EXPECT_EQ(std::get<VehicleError>(job).type, "orderError");

  m = order("o1", 0, {"H1", "A1"}, 0, 100, {{1, action("a1", "beep")}});
  job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleError>(job));
  EXPECT_NE(std::get<VehicleError>(job).description.find("'beep'"), std::string::npos);

  m = order("o1", 0, {"H1", "nowhere"});
  job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleError>(job));
  EXPECT_EQ(std::get<VehicleError>(job).type, "noRouteError");

  // A pick alone: a transport whose drop comes later; a drop alone only for a robot that carries.
  m = order("o1", 0, {"H1", "A1"}, 0, 100, {{1, action("a1", "pick")}});
  job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleJob>(job));
  EXPECT_EQ(std::get<VehicleJob>(job).order.kind, orders::OrderKind::kTransport);
  EXPECT_TRUE(std::get<VehicleJob>(job).order.drop_area_id.empty());
  EXPECT_EQ(std::get<VehicleJob>(job).goal_node, 2u);
  m = order("o2", 0, {"A1", "A2"}, 0, 100, {{1, action("a2", "drop")}});
  job = job_of("o2", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  EXPECT_TRUE(std::holds_alternative<VehicleError>(job));
  job = job_of("o2", nodes_of(m), {}, site.site, site.graph.graph, true, true, m);
  ASSERT_TRUE(std::holds_alternative<VehicleJob>(job));
  EXPECT_EQ(std::get<VehicleJob>(job).order.drop_area_id, "A2");

  // A position on the site but on no road or place is a waypoint; one off the site is no route.
  m = order("o1", 0, {"H1", "w", "H2"});
  m["nodes"][1]["nodePosition"] = {{"x", 1.25}, {"y", 1.3}, {"mapId", "table_a"}};
  job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleJob>(job));
  EXPECT_EQ(std::get<VehicleJob>(job).nodes.at(0).point, -1);
  m["nodes"][1]["nodePosition"]["x"] = 40.0;
  job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleError>(job));
  EXPECT_NE(std::get<VehicleError>(job).description.find("outside site"), std::string::npos);

  m = order("o1", 0, {"H1", "p3", "H2"});
  job = job_of("o1", nodes_of(m), {}, site.site, site.graph.graph, true, false, m);
  ASSERT_TRUE(std::holds_alternative<VehicleJob>(job));
  EXPECT_EQ(std::get<VehicleJob>(job).order.kind, orders::OrderKind::kMove);
  EXPECT_EQ(std::get<VehicleJob>(job).order.drop_area_id, "H2");
  EXPECT_EQ(std::get<VehicleJob>(job).nodes.at(0).point, 3);
}

TEST(VehicleDriveTest, GrantsUpToTheBaseAndLeadsTheRouteThroughItsNodes) {
  const map::RoadGraph& graph = table_a().graph.graph;
  // A robot's own route along 8 graph points; the order's nodes lie on it at its 3rd and 6th.
  std::vector<int> route = shortest_road(graph, 0, static_cast<int>(graph.points.size()) / 2);
  ASSERT_GE(route.size(), 8u);
  route.resize(8);
  ASSERT_EQ(route.size(), 8u);
  std::vector<NodeOnSite> leg{{2, true, route[2], "", {}}, {4, false, route[5], "", {}}};
  VehicleDrive drive;
  drive.set_leg(leg);
  robot::TrafficRoute own;
  own.version = 10;
  own.points = route;
  auto permit = drive.permit(own, graph);
  ASSERT_TRUE(permit);
  EXPECT_EQ(permit->version, 10u);
  EXPECT_TRUE(permit->route.empty());
  EXPECT_EQ(permit->granted_index, 2);

  own.progress = 0.5 * permit->granted_distance;
  EXPECT_TRUE(drive.passed(own).empty());
  own.progress = permit->granted_distance;
  EXPECT_EQ(drive.passed(own), std::vector<std::uint32_t>{2});

  leg[1].released = true;
  drive.set_leg(leg);
  permit = drive.permit(own, graph);
  ASSERT_TRUE(permit);
  EXPECT_EQ(permit->granted_index, 7);  // the leg's end released: the whole route

  // A node off the robot's own route: the route is handed over through it, with a version of
  // the traffic manager's kind (odd).
  const int aside = graph.successors[static_cast<std::size_t>(route[7])].front();
  VehicleDrive detour;
  detour.set_leg({{2, true, aside, "", {}}});
  robot::TrafficRoute short_route;
  short_route.version = 12;
  short_route.points = {route[0], route[1], route[2]};
  permit = detour.permit(short_route, graph);
  ASSERT_TRUE(permit);
  EXPECT_EQ(permit->version, 13u);
  ASSERT_FALSE(permit->route.empty());
  EXPECT_NE(std::find(permit->route.begin(), permit->route.end(), aside), permit->route.end());
  EXPECT_EQ(permit->route.back(), route[2]);
}

}  // namespace
}  // namespace fleet::vda5050
