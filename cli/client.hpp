#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "dds/topics.hpp"

namespace fleet::cli {

/// fleetctl's own DDS participant: finds the server, sends requests and commands, reads state.
class FleetClient {
 public:
  explicit FleetClient(std::uint32_t domain);

  std::uint32_t domain() const { return participant_.domain(); }
  dds::Participant& participant() { return participant_; }

  /// The server's ServerInfo, or nothing when no server answers within `timeout`.
  std::optional<model::ServerInfo> find_server(std::chrono::milliseconds timeout);

  /// Sends an order request and waits for the server's reply (nothing on timeout).
  std::optional<model::RequestReply> request_order(model::OrderRequest request, std::chrono::milliseconds timeout);

  /// Sends a command and waits for the server's reply (nothing on timeout).
  std::optional<model::RequestReply> send_command(model::Command command, std::chrono::milliseconds timeout);

  /// Follows one order until it ends, calling `on_change` on every new state or phase; returns
  /// its final OrderInfo, or nothing when the server went away or `timeout` passed.
  std::optional<model::OrderInfo> follow_order(std::int64_t order_id,
                                               const std::function<void(const model::OrderInfo&)>& on_change,
                                               std::chrono::milliseconds timeout = kNoTimeout);

  /// Reads RobotState for `window` and returns the newest of each robot.
  std::map<std::string, model::RobotState> robot_states(std::chrono::milliseconds window);

  /// Every designated static obstacle and whether it is on (latched), read during `window`.
  std::map<std::string, model::StaticObstacleState> obstacles(std::chrono::milliseconds window);

  /// Latest OrderInfo of every order, read during `window`.
  std::map<std::int64_t, model::OrderInfo> orders(std::chrono::milliseconds window);

  /// The OrderInfo samples that arrived since the last call (without waiting), also kept in
  /// known_orders().
  std::vector<model::OrderInfo> take_order_updates();
  /// Latest OrderInfo of every order seen so far.
  const std::map<std::int64_t, model::OrderInfo>& known_orders() const { return orders_; }

  /// Where every pallet stands or who carries it (latched PalletTruth), read during `window`
  /// (at least once, so a zero window returns what has arrived already).
  std::map<int, model::PalletTruth> pallets(std::chrono::milliseconds window);

  /// Reads the server's liveliness now; see server_alive().
  bool check_server();

  /// Whether the server is still there: false once its ServerInfo writer has been gone for
  /// longer than kServerGoneGrace. A lease missed for a moment on a loaded machine (Cyclone's
  /// participant lease is 1 s) must not make a client give up on a live server.
  bool server_alive() const;
  static constexpr std::chrono::seconds kServerGoneGrace{5};
  /// "No limit" that still compares safely with steady_clock's nanosecond durations (a year;
  /// milliseconds::max() would overflow in the comparison).
  static constexpr std::chrono::milliseconds kNoTimeout = std::chrono::hours(24 * 365);

 private:
  std::optional<model::RequestReply> await_reply(const std::string& request_id, std::chrono::milliseconds timeout);
  void poll_server_info();

  dds::Participant participant_;
  dds::Reader<model::ServerInfo> server_info_reader_;
  dds::Reader<model::RequestReply> reply_reader_;
  dds::Reader<model::OrderInfo> order_info_reader_;
  dds::Reader<model::RobotState> robot_state_reader_;
  dds::Reader<model::StaticObstacleState> obstacle_reader_;
  dds::Reader<model::PalletTruth> pallet_reader_;
  dds::Writer<model::OrderRequest> request_writer_;
  dds::Writer<model::Command> command_writer_;
  std::optional<model::ServerInfo> server_info_;
  bool server_alive_ = false;
  std::optional<std::chrono::steady_clock::time_point> server_gone_since_;
  std::map<std::int64_t, model::OrderInfo> orders_;
  std::map<int, model::PalletTruth> pallets_;
};

/// A request id unique across processes and time.
std::string make_request_id();

}  // namespace fleet::cli
