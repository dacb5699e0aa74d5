#pragma once

// A real fleet-server with robots played by the test over DDS: the server hears from them only
// what the test makes them say.

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <thread>

#include "cli/client.hpp"
#include "config/fleet_config.hpp"
#include "dds/qos.hpp"
#include "fleet_harness.hpp"
#include "map/road_graph_builder.hpp"
#include "map/site_map.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::testing {

using namespace std::chrono_literals;

template <typename Predicate>
inline bool eventually(Predicate p, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    if (p()) return true;
    std::this_thread::sleep_for(20ms);
  }
  return p();
}

/// The orders as the server serving now publishes them, once `wanted` of them are DONE (or the
/// time is up).
inline std::map<std::int64_t, model::OrderInfo> orders_once_done(cli::FleetClient& client, long wanted,
                                                                 std::chrono::seconds within) {
  std::map<std::int64_t, model::OrderInfo> orders;
  const auto deadline = std::chrono::steady_clock::now() + within;
  for (;;) {
    orders = client.orders(1500ms);
    long finished = 0;
    for (const auto& [id, info] : orders) finished += info.state == "DONE";
    if (finished >= wanted || std::chrono::steady_clock::now() > deadline) return orders;
  }
}

/// Asks the server for an order from A1 (which holds a pallet) to A2.
inline std::optional<model::RequestReply> order_a1_to_a2(cli::FleetClient& client) {
  model::OrderRequest request;
  request.pick_area = "A1";
  request.drop_area = "A2";
  return client.request_order(request, 5s);
}

/// Whether order `id` is in `state` (DONE, FAILED, ...) by the OrderInfo read now.
inline bool order_in_state(cli::FleetClient& client, std::int64_t id, const std::string& state) {
  const auto known = client.orders(50ms);
  const auto it = known.find(id);
  return it != known.end() && it->second.state == state;
}

/// Whether order `id` is seen in `phase` within `timeout` (on `robot`, unless it is empty).
inline bool reaches_phase(cli::FleetClient& client, std::int64_t id, const std::string& phase, const std::string& robot,
                          std::chrono::milliseconds timeout) {
  return eventually(
      [&] {
        const auto o = client.orders(50ms);
        auto it = o.find(id);
        return it != o.end() && it->second.phase == phase && (robot.empty() || it->second.robot_id == robot);
      },
      timeout);
}

/// A robot (fl1 at home H1 unless told) played by the test over DDS: the server hears from it only
/// what the test makes it say, so it can fail a search, fall silent, or send a route, at a chosen
/// moment.
struct ScriptedRobot {
  dds::Writer<model::RobotState> state_writer;
  dds::Writer<model::OrderReport> report_writer;
  dds::Reader<model::OrderAssignment> orders;
  model::RobotState state;

  explicit ScriptedRobot(cli::FleetClient& client, const std::string& robot_id = "fl1",
                         geometry::Pose2 at = {0.83, 0.82, -1.57})  // home H1
      : state_writer(client.participant(), dds::qos::robot_state()),
        report_writer(client.participant(), dds::qos::latched_state()),
        orders(client.participant(), dds::qos::latched_state()) {
    state.robot_id = robot_id;
    state.fleet_id = "forklifts";
    state.map_id = "table_a";
    state.pose = at;
    state.task_state = "IDLE";
  }
  void publish_state() { state_writer.write(state); }
  /// Publishing its state (within the 0.5 s deadline of RobotState) until `done`.
  template <typename Predicate>
  bool keeps_answering_until(Predicate done, std::chrono::milliseconds timeout) {
    return eventually(
        [&] {
          publish_state();
          return done();
        },
        timeout);
  }
  bool registers_with(const FleetHarness& fleet) {
    return keeps_answering_until(
        [&] {
          return fleet.log_of("fleet-server").find("robot " + state.robot_id + " (forklifts) registered") !=
                 std::string::npos;
        },
        10s);
  }
  std::optional<model::OrderAssignment> assignment_of(std::int64_t order_id) {
    std::optional<model::OrderAssignment> assignment;
    keeps_answering_until(
        [&] {
          orders.take_data([&](model::OrderAssignment&& a) {
            if (a.order_id == order_id && a.robot_id == state.robot_id && !a.cancelled) assignment = a;
          });
          return assignment.has_value();
        },
        10s);
    return assignment;
  }
  void report(const model::OrderAssignment& assignment, const std::string& status, const std::string& reason = {}) {
    model::OrderReport r;
    r.order_id = assignment.order_id;
    r.robot_id = state.robot_id;
    r.update_id = assignment.update_id;
    r.status = status;
    r.reason = reason;
    r.carrying_pallet = state.carrying_pallet;
    report_writer.write(r);
  }
};

/// A real server on `domain` and the scripted robot fl1.
struct ScriptedFleet {
  FleetHarness fleet;
  cli::FleetClient client;
  ScriptedRobot robot;

  explicit ScriptedFleet(int domain) : fleet(domain, 10.0), client(domain), robot(client) {}
  std::string server_log() const { return fleet.log_of("fleet-server"); }
  /// Starts the server, registers fl1 and orders a pallet from A1 to A2: fl1's assignment.
  std::optional<model::OrderAssignment> start_with_order() {
    fleet.start_server();
    if (!client.find_server(5s) || !robot.registers_with(fleet)) return std::nullopt;
    const auto reply = order_a1_to_a2(client);
    if (!reply || !reply->accepted) return std::nullopt;
    return robot.assignment_of(reply->order_id);
  }
  /// Whether order `id` is seen in `phase` on fl1, fl1 answering meanwhile.
  bool order_reaches(std::int64_t id, const std::string& phase) {
    return robot.keeps_answering_until(
        [&] {
          const auto o = client.orders(50ms);
          const auto it = o.find(id);
          return it != o.end() && it->second.phase == phase && it->second.robot_id == "fl1";
        },
        10s);
  }
  /// start_with_order, then fl1 accepts the order and drives off towards A1.
  std::optional<model::OrderAssignment> start_on_the_way_to_pick() {
    auto assignment = start_with_order();
    if (!assignment) return std::nullopt;
    robot.state.order_id = assignment->order_id;
    robot.state.task_state = "TRACK_PATH";
    robot.report(*assignment, "ACCEPTED");
    robot.report(*assignment, "TO_PICK");
    if (!order_reaches(assignment->order_id, "TO_PICK")) return std::nullopt;
    return assignment;
  }
};

/// table_a's roads as the server's traffic manager grants them under config/fleet.yaml, for
/// scripting routes it accepts.
struct TableARoutes {
  config::FleetConfig config = config::load_fleet_config(fleet::test::source_path("/config/fleet.yaml"));
  map::SiteMap site = map::load_site_map(fleet::test::source_path("/maps/table_a.yaml"));
  traffic::TrafficManager manager{site.graph.graph, traffic::configuration_from(config)};

  const map::RoadGraph& graph() const { return manager.route_graph(); }
  int point_near(double x, double y) const { return map::nearest_point(graph(), x, y); }
  std::vector<int> shortest(int from, int to) { return manager.search().shortest(from, to); }
};

}  // namespace fleet::testing
