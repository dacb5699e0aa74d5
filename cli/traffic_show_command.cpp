// fleetctl traffic show [ROBOT]: what traffic grants every robot and whom it waits for, read from
// the agents' TrafficRequests and the server's TrafficGrants on the wire.

#include <algorithm>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/online_commands.hpp"
#include "cli/online_support.hpp"
#include "common/args.hpp"
#include "model/names.hpp"
#include "model/traffic_requests.hpp"

namespace fleet::cli {

namespace {

struct TrafficView {
  std::optional<model::TrafficRequest> request;
  std::optional<model::TrafficGrant> grant;
};

std::map<std::string, TrafficView> read_traffic(FleetClient& client, std::chrono::milliseconds window) {
  dds::Reader<model::TrafficGrant> grants(client.participant(), dds::qos::live_state(), model::every_robot_partition());
  dds::Reader<model::TrafficRequest> requests(client.participant(), dds::qos::live_state(),
                                              dds::robot_report_partitions());
  dds::Reader<model::TrafficProgress> progress(client.participant(), dds::qos::live_state(),
                                               dds::robot_report_partitions());
  model::TrafficRequestJoin join;
  std::map<std::string, TrafficView> views;
  const auto deadline = std::chrono::steady_clock::now() + window;
  while (std::chrono::steady_clock::now() < deadline) {
    grants.take_data([&](model::TrafficGrant&& g) { views[g.robot_id].grant = std::move(g); });
    requests.take_data([&](model::TrafficRequest&& r) { views[r.robot_id].request = join.route(std::move(r)); });
    progress.take_data([&](model::TrafficProgress&& p) {
      if (auto request = join.progress(p)) views[p.robot_id].request = std::move(*request);
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return views;
}

nlohmann::json view_json(const std::string& robot, const TrafficView& view) {
  nlohmann::json row{{"robot_id", robot}};
  if (view.request) {
    row["route"] = view.request->points;
    row["progress_m"] = view.request->progress;
    row["work_area"] = !view.request->work_area.empty();
  }
  if (const auto& g = view.grant) {
    row["status"] = g->status;
    row["granted_index"] = g->granted_index;
    row["granted_m"] = g->granted_distance;
    row["waited_s"] = g->waited_s;
    row["waits_for"] = g->blocked_by;
    if (!g->instruction.empty()) row["instruction"] = g->instruction;
    // The places it may drive through now: its route from the start up to the grant's end.
    if (view.request && g->version == view.request->version && g->granted_index >= 0) {
      const auto& points = view.request->points;
      const auto end = std::min<std::size_t>(points.size(), static_cast<std::size_t>(g->granted_index) + 1);
      row["granted_points"] = std::vector<std::int32_t>(points.begin(), points.begin() + static_cast<long>(end));
    }
  }
  return row;
}

/// Who `robot` waits for, and whom they wait for, each robot once: "fl4 waits for fl6, which
/// waits for fl2".
std::string wait_chain(const std::string& robot, const std::map<std::string, TrafficView>& views) {
  std::ostringstream out;
  std::set<std::string> seen{robot};
  std::vector<std::string> front{robot};
  int depth = 0;
  while (!front.empty() && depth < 8) {
    std::vector<std::string> next;
    for (const auto& r : front) {
      const auto it = views.find(r);
      if (it == views.end() || !it->second.grant || it->second.grant->blocked_by.empty()) continue;
      out << (out.tellp() > 0 ? "; " : "") << r << " waits for " << model::join(it->second.grant->blocked_by);
      for (const auto& b : it->second.grant->blocked_by) {
        if (seen.insert(b).second) next.push_back(b);
      }
    }
    front = std::move(next);
    ++depth;
  }
  const std::string text = out.str();
  return text.empty() ? robot + " waits for nobody" : text;
}

}  // namespace

int traffic_show_command(const CommandArgs& command, const Connection& connection, std::ostream& out,
                         std::ostream& err) {
  try {
    if (command.args.empty() || command.args[0] != "show") throw ArgError("traffic needs a subcommand: show [ROBOT]");
    const CommandFlags args("traffic", "show", std::vector<std::string>(command.args.begin() + 1, command.args.end()));
    const std::vector<std::string>& rest = args.positionals();
    if (rest.size() > 1) throw ArgError("unexpected argument '" + rest[1] + "'");
    FleetClient client(connection.domain);
    const model::ServerInfo info = require_server(client, connection);
    if (!rest.empty()) require_known("robot", rest[0], info.robots);
    // Half as long again as the agents take to repeat an unchanged route: every one is heard.
    const auto views = read_traffic(client, std::chrono::duration_cast<std::chrono::milliseconds>(
                                                std::chrono::duration<double>(1.5 * model::kRouteRepeatWallS)));
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& [robot, view] : views) {
      if (rest.empty() || robot == rest[0]) rows.push_back(view_json(robot, view));
    }
    if (!rest.empty()) {
      nlohmann::json one = rows.empty() ? nlohmann::json{{"robot_id", rest[0]}} : rows[0];
      one["wait_chain"] = wait_chain(rest[0], views);
      if (command.json) {
        out << one.dump() << "\n";
        return kExitOk;
      }
      out << rest[0] << ": ";
      if (!one.contains("status")) {
        out << "no grant seen (not on the roads, or traffic control is off)\n";
        return kExitOk;
      }
      out << one["status"].get<std::string>() << ", granted " << std::fixed << std::setprecision(2)
          << one["granted_m"].get<double>() << " m, waited " << std::setprecision(1) << one["waited_s"].get<double>()
          << " s\n  " << one["wait_chain"].get<std::string>() << "\n";
      if (one.contains("granted_points")) {
        out << "  granted route points:";
        for (const auto& p : one["granted_points"]) out << " " << p.get<int>();
        out << "\n";
      }
      return kExitOk;
    }
    if (command.json) {
      out << rows.dump() << "\n";
      return kExitOk;
    }
    out << std::left << std::setw(8) << "ROBOT" << std::setw(14) << "STATUS" << std::setw(26) << "GRANTED"
        << std::setw(9) << "WAITED"
        << "WAITS FOR\n";
    for (const auto& r : rows) {
      std::ostringstream granted, waited;
      if (r.contains("status")) {
        granted << std::fixed << std::setprecision(2) << r["granted_m"].get<double>() << " m, point "
                << r["granted_index"].get<long>() + 1 << " of " << r.value("route", nlohmann::json::array()).size();
        waited << std::fixed << std::setprecision(1) << r["waited_s"].get<double>() << " s";
      }
      const auto waits = r.value("waits_for", std::vector<std::string>{});
      out << std::left << std::setw(8) << r["robot_id"].get<std::string>() << std::setw(14) << r.value("status", "-")
          << std::setw(26) << granted.str() << std::setw(9) << waited.str()
          << (waits.empty() ? "-" : model::join(waits)) << "\n";
    }
    if (rows.empty()) out << "no traffic request or grant seen (traffic control off, or no robot on the roads)\n";
    return kExitOk;
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

}  // namespace fleet::cli
