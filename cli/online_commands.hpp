#pragma once

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "cli/commands.hpp"

namespace fleet::cli {

/// Options shared by commands that talk to a running server.
struct Connection {
  std::uint32_t domain = 0;
  std::chrono::milliseconds timeout{3000};  ///< how long to look for the server
  /// --timeout was given: commands that follow orders (order watch, --wait) stop after it too.
  bool timeout_given = false;
};

int order_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int obstacle_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int robot_control_command(const std::string& verb, const CommandArgs& args, const Connection& connection,
                          std::ostream& out, std::ostream& err);
/// `auto-orders on|off`: switches the server's automatic orders.
int auto_orders_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int map_list_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int stats_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int routing_age_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
/// `order watch [ID]`: live progress of one order or all of them.
int order_watch(const std::vector<std::string>& args, const CommandArgs& command, const Connection& connection,
                std::ostream& out, std::ostream& err);
/// `inject`: random valid orders at a rate, or the rows of a CSV file.
int inject_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int robots_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
/// `servers`: the fleet's server processes, which is active and since when, each standby's lag.
int servers_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
/// `traffic show [ROBOT]`: every robot's grant and whom it waits for, or one robot's chain of waits.
int traffic_show_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);

}  // namespace fleet::cli
