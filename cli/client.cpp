#include "cli/client.hpp"

#include <unistd.h>

#include <random>
#include <thread>

#include "orders/order.hpp"

namespace fleet::cli {

using namespace std::chrono_literals;

std::string make_request_id() {
  static std::mt19937_64 rng(std::random_device{}() ^ static_cast<std::uint64_t>(getpid()));
  static int counter = 0;
  return "fleetctl-" + std::to_string(getpid()) + "-" + std::to_string(++counter) + "-" +
         std::to_string(rng() % 100000);
}

FleetClient::FleetClient(std::uint32_t domain)
    : participant_(domain),
      server_info_reader_(participant_, dds::qos::latched_state()),
      reply_reader_(participant_, dds::qos::latched_state()),
      order_info_reader_(participant_, dds::qos::latched_state()),
      robot_state_reader_(participant_, dds::qos::live_state(), dds::robot_report_partitions()),
      obstacle_reader_(participant_, dds::qos::latched_state()),
      pallet_reader_(participant_, dds::qos::latched_state()),
      request_writer_(participant_, dds::qos::requests()),
      command_writer_(participant_, dds::qos::requests()) {}

void FleetClient::poll_server_info() {
  server_info_reader_.take([&](model::ServerInfo&& info, const dds::SampleInfo& sample) {
    if (sample.valid_data || sample.alive) {
      if (sample.valid_data) server_info_ = std::move(info);
      server_alive_ = true;
      server_gone_since_.reset();
    } else if (!server_gone_since_) {
      server_gone_since_ = std::chrono::steady_clock::now();
    }
  });
}

bool FleetClient::server_alive() const {
  return server_alive_ &&
         (!server_gone_since_ || std::chrono::steady_clock::now() - *server_gone_since_ < kServerGoneGrace);
}

std::optional<model::ServerInfo> FleetClient::find_server(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    poll_server_info();
    if (server_info_ && server_alive()) return server_info_;
    std::this_thread::sleep_for(10ms);
  }
  return std::nullopt;
}

std::optional<model::RequestReply> FleetClient::await_reply(const std::string& request_id,
                                                            std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < deadline) {
    std::optional<model::RequestReply> found;
    reply_reader_.take_data([&](model::RequestReply&& reply) {
      if (reply.request_id == request_id) found = std::move(reply);
    });
    if (found) return found;
    std::this_thread::sleep_for(5ms);
  }
  return std::nullopt;
}

std::optional<model::RequestReply> FleetClient::request_order(model::OrderRequest request,
                                                              std::chrono::milliseconds timeout) {
  if (request.request_id.empty()) request.request_id = make_request_id();
  // Volatile requests reach only readers matched at write time: wait for the server's.
  if (!request_writer_.wait_for_readers(1, timeout)) return std::nullopt;
  request_writer_.write(request);
  return await_reply(request.request_id, timeout);
}

std::optional<model::RequestReply> FleetClient::send_command(model::Command command,
                                                             std::chrono::milliseconds timeout) {
  if (command.request_id.empty()) command.request_id = make_request_id();
  if (!command_writer_.wait_for_readers(1, timeout)) return std::nullopt;
  command_writer_.write(command);
  return await_reply(command.request_id, timeout);
}

std::optional<model::OrderInfo> FleetClient::follow_order(std::int64_t order_id,
                                                          const std::function<void(const model::OrderInfo&)>& on_change,
                                                          std::chrono::milliseconds timeout) {
  std::string last_state, last_phase;
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < timeout) {
    std::optional<model::OrderInfo> latest;
    order_info_reader_.take_data([&](model::OrderInfo&& info) {
      if (info.order_id == order_id) latest = info;
      orders_[info.order_id] = std::move(info);
    });
    if (latest && (latest->state != last_state || latest->phase != last_phase)) {
      last_state = latest->state;
      last_phase = latest->phase;
      on_change(*latest);
      const auto status = orders::parse_status(latest->state);
      if (status && orders::is_final(*status)) return latest;
    }
    poll_server_info();
    if (!server_alive()) return std::nullopt;
    std::this_thread::sleep_for(10ms);
  }
  return std::nullopt;
}

std::map<std::string, model::RobotState> FleetClient::robot_states(std::chrono::milliseconds window) {
  std::map<std::string, model::RobotState> states;
  const auto deadline = std::chrono::steady_clock::now() + window;
  while (std::chrono::steady_clock::now() < deadline) {
    robot_state_reader_.take_data([&](model::RobotState&& s) { states[s.robot_id] = std::move(s); });
    std::this_thread::sleep_for(10ms);
  }
  return states;
}

std::map<std::string, model::StaticObstacleState> FleetClient::obstacles(std::chrono::milliseconds window) {
  std::map<std::string, model::StaticObstacleState> out;
  const auto deadline = std::chrono::steady_clock::now() + window;
  while (std::chrono::steady_clock::now() < deadline) {
    obstacle_reader_.take_data([&](model::StaticObstacleState&& o) { out[o.obstacle_id] = std::move(o); });
    std::this_thread::sleep_for(10ms);
  }
  return out;
}

std::map<std::int64_t, model::OrderInfo> FleetClient::orders(std::chrono::milliseconds window) {
  const auto deadline = std::chrono::steady_clock::now() + window;
  while (std::chrono::steady_clock::now() < deadline) {
    order_info_reader_.take_data([&](model::OrderInfo&& info) { orders_[info.order_id] = std::move(info); });
    std::this_thread::sleep_for(10ms);
  }
  return orders_;
}

std::vector<model::OrderInfo> FleetClient::take_order_updates() {
  std::vector<model::OrderInfo> updates;
  order_info_reader_.take_data([&](model::OrderInfo&& info) {
    orders_[info.order_id] = info;
    updates.push_back(std::move(info));
  });
  return updates;
}

std::map<int, model::PalletTruth> FleetClient::pallets(std::chrono::milliseconds window) {
  const auto deadline = std::chrono::steady_clock::now() + window;
  while (true) {
    pallet_reader_.take_data([&](model::PalletTruth&& p) { pallets_[p.pallet_id] = std::move(p); });
    if (std::chrono::steady_clock::now() >= deadline) return pallets_;
    std::this_thread::sleep_for(10ms);
  }
}

bool FleetClient::check_server() {
  poll_server_info();
  return server_alive();
}

}  // namespace fleet::cli
