// `fleetctl servers`: the fleet's server processes as they announce themselves (ServerLoad, once a
// second each): which is active, in which term and since when, and how long ago each standby last
// heard the active one.

#include <algorithm>
#include <chrono>
#include <ctime>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/online_commands.hpp"
#include "cli/online_support.hpp"
#include "common/clock.hpp"
#include "dds/qos.hpp"

namespace fleet::cli {

namespace {

/// "2026-12-06 19:26:28" in local time.
std::string local_time(std::int64_t unix_ms) {
  const std::time_t t = static_cast<std::time_t>(unix_ms / 1000);
  std::tm tm{};
  localtime_r(&t, &tm);
  std::ostringstream out;
  out << std::put_time(&tm, "%Y-%m-%d %H:%M:%S");
  return out.str();
}

}  // namespace

int servers_command(const CommandArgs& command, const Connection& connection, std::ostream& out, std::ostream& err) {
  try {
    const CommandFlags args("servers", "", command.args);
    FleetClient client(connection.domain);
    dds::Reader<model::ServerLoad> reader(client.participant(), dds::qos::live_state());
    // Every server writes once a second: listen a little longer than that.
    const auto listen = connection.timeout_given ? connection.timeout : std::chrono::milliseconds(1500);
    std::map<std::string, model::ServerLoad> servers;
    const auto end = std::chrono::steady_clock::now() + listen;
    while (std::chrono::steady_clock::now() < end) {
      reader.take_data([&](model::ServerLoad&& load) { servers[load.server_id] = std::move(load); });
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (servers.empty()) {
      throw CommandExit{kExitNoServer, "no fleet-server on DDS domain " + std::to_string(connection.domain)};
    }
    const double now_s = SimClock::wall_now();
    nlohmann::json doc = nlohmann::json::array();
    for (const auto& [id, s] : servers) {
      nlohmann::json row{{"server_id", id},
                         {"role", s.active ? "active" : "standby"},
                         {"term", s.term},
                         {"since_unix_ms", s.since_unix_ms},
                         {"for_s", now_s - static_cast<double>(s.since_unix_ms) / 1000.0}};
      if (s.active) {
        row["took_over"] = s.took_over;
        row["robots"] = s.robots;
      } else {
        row["active_heard_s_ago"] = s.active_heard_s_ago;
      }
      doc.push_back(row);
    }
    if (command.json) {
      out << nlohmann::json{{"servers", doc}}.dump() << "\n";
      return kExitOk;
    }
    out << std::left << std::setw(24) << "SERVER" << std::setw(9) << "ROLE" << std::setw(6) << "TERM" << std::setw(21)
        << "SINCE"
        << "DETAIL\n";
    for (const auto& [id, s] : servers) {
      out << std::left << std::setw(24) << id << std::setw(9) << (s.active ? "active" : "standby") << std::setw(6)
          << s.term << std::setw(21) << local_time(s.since_unix_ms);
      std::ostringstream detail;
      detail << std::fixed << std::setprecision(1);
      if (s.active) {
        detail << s.robots << " robots" << (s.took_over ? ", took over" : "");
      } else {
        detail << "heard the active server " << s.active_heard_s_ago << " s ago";
      }
      out << detail.str() << "\n";
    }
    const auto active = std::count_if(servers.begin(), servers.end(), [](const auto& s) { return s.second.active; });
    if (active != 1) err << "fleetctl: " << active << " active servers heard (one expected)\n";
    return kExitOk;
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

}  // namespace fleet::cli
