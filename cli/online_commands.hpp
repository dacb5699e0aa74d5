#pragma once

#include <chrono>
#include <cstdint>
#include <iosfwd>

#include "cli/commands.hpp"

namespace fleet::cli {

/// Options shared by commands that talk to a running server.
struct Connection {
  std::uint32_t domain = 0;
  std::chrono::milliseconds timeout{3000};  ///< how long to look for the server
};

int order_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int obstacle_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int robot_control_command(const std::string& verb, const CommandArgs& args, const Connection& connection,
                          std::ostream& out, std::ostream& err);
int map_list_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int stats_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int routing_age_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);
int robots_command(const CommandArgs& args, const Connection& connection, std::ostream& out, std::ostream& err);

}  // namespace fleet::cli
