#include "cli/online_support.hpp"

#include <algorithm>
#include <ostream>

#include "common/args.hpp"
#include "model/names.hpp"
#include "orders/order.hpp"
#include "orders/order_kind.hpp"

namespace fleet::cli {

int report_failure(bool json, int code, const std::string& message, std::ostream& out, std::ostream& err) {
  err << "fleetctl: " << message << "\n";
  if (json) {
    nlohmann::json doc{{"error", message}, {"exit_code", code}};
    // "--from: ..." (a command's own check) or "flag --from: ..." (the argument parser's).
    const std::size_t flag = message.starts_with("--") ? 0 : message.starts_with("flag --") ? 5 : std::string::npos;
    if (flag != std::string::npos) {
      const auto colon = message.find(':', flag);
      if (colon != std::string::npos && message.find(' ', flag) > colon)
        doc["field"] = message.substr(flag + 2, colon - flag - 2);
    }
    out << doc.dump() << "\n" << std::flush;
  }
  return code;
}

model::ServerInfo require_server(FleetClient& client, const Connection& connection) {
  auto info = client.find_server(connection.timeout);
  if (!info) throw CommandExit{kExitNoServer, "no fleet-server on DDS domain " + std::to_string(connection.domain)};
  return *info;
}

void require_known(const std::string& what, const std::string& name, const std::vector<std::string>& valid) {
  if (std::find(valid.begin(), valid.end(), name) == valid.end()) {
    throw CommandExit{kExitBadInput, model::unknown_name_message(what, name, valid)};
  }
}

std::int64_t order_id_of(const std::string& text) {
  try {
    std::size_t used = 0;
    const long long id = std::stoll(text, &used);
    if (used == text.size() && id > 0) return id;
  } catch (const std::exception&) {
  }
  throw ArgError("order id '" + text + "' is not a positive number");
}

nlohmann::json order_json(const model::OrderInfo& o) {
  nlohmann::json history = nlohmann::json::array();
  for (const auto& e : o.history) {
    history.push_back({{"sim_time", e.sim_time},
                       {"state", e.state},
                       {"phase", e.phase},
                       {"robot_id", e.robot_id},
                       {"reason", e.reason},
                       {"robot_x", e.robot_x},
                       {"robot_y", e.robot_y}});
  }
  // The order's VDA 5050 nodes with their actions.
  nlohmann::json steps = nlohmann::json::array();
  const auto kind = orders::parse_kind(o.kind.empty() ? "transport" : o.kind);
  for (const auto& step : orders::order_steps(kind.value_or(orders::OrderKind::kTransport), o.pick_area, o.drop_area)) {
    steps.push_back({{"place", step.place}, {"actions", step.actions}});
  }
  // The step being executed, from the phase the robot reports (null before it starts).
  const auto phase = orders::parse_phase(o.phase);
  const nlohmann::json step = phase ? nlohmann::json(orders::step_index(*phase)) : nlohmann::json();
  return {{"order_id", o.order_id},
          {"kind", o.kind},
          {"steps", steps},
          {"step", step},
          {"pick_area", o.pick_area},
          {"drop_area", o.drop_area},
          {"robot_id", o.robot_id},
          {"state", o.state},
          {"phase", o.phase},
          {"reason", o.reason},
          {"priority", o.priority},
          {"created_sim", o.created_sim},
          {"updated_sim", o.updated_sim},
          {"history", history},
          {"cause", o.cause},
          {"caused_by", o.caused_by}};
}

}  // namespace fleet::cli
