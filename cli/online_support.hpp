#pragma once

// Helpers shared by the commands that talk to a running fleet-server.

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/client.hpp"
#include "cli/online_commands.hpp"

namespace fleet::cli {

/// How fleetctl ends on an error: "fleetctl: MESSAGE" on stderr and, with --json, one JSON
/// document as the last line on stdout: {"error", "exit_code"}, with "field" when the message
/// starts with the flag it is about ("--from: ..."). Returns `code`.
int report_failure(bool json, int code, const std::string& message, std::ostream& out, std::ostream& err);

/// Thrown to leave a command with an exit code after printing `message` to stderr.
struct CommandExit {
  int code;
  std::string message;
};

/// The server's ServerInfo; CommandExit with kExitNoServer ("no fleet-server on DDS domain N")
/// when none answers within the connection's timeout.
model::ServerInfo require_server(FleetClient& client, const Connection& connection);

/// CommandExit with kExitBadInput naming `name` and listing the valid ones when it is unknown.
void require_known(const std::string& what, const std::string& name, const std::vector<std::string>& valid);

/// A positive order id from the command line; ArgError otherwise.
std::int64_t order_id_of(const std::string& text);

/// An order with its history, as `order show --json` prints it.
nlohmann::json order_json(const model::OrderInfo& order);

}  // namespace fleet::cli
