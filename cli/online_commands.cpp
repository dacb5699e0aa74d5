#include "cli/online_commands.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/online_support.hpp"
#include "common/args.hpp"
#include "common/clock.hpp"
#include "common/paths.hpp"
#include "common/percentile.hpp"
#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "model/names.hpp"
#include "monitor/order_accounting.hpp"
#include "orders/order.hpp"
#include "orders/order_request_check.hpp"
#include "orders/pick_lines.hpp"
#include "traffic/order_names.hpp"

namespace fleet::cli {

namespace {

int order_add(const CommandFlags& args, const CommandArgs& command, const Connection& connection, std::ostream& out,
              std::ostream& err) {
  model::OrderRequest request;
  request.kind = args.value("kind").value_or("");
  const bool move = request.kind == "move";
  const auto from = args.value("from");
  const auto to = args.value("to");
  const auto lines_file = args.value("lines");
  std::vector<orders::PickLine> lines;
  if (lines_file) {
    if (request.kind != "pick") throw ArgError("--lines is for --kind pick");
    if (from) throw ArgError("order add --kind pick --lines takes its places from the lines, not --from");
    std::ifstream in(*lines_file);
    if (!in) throw ArgError("--lines: cannot read '" + *lines_file + "'");
    std::ostringstream text;
    text << in.rdbuf();
    request.lines = text.str();
    lines = orders::parse_pick_lines(request.lines, *lines_file);
  }
  request.handling = args.value("handling").value_or("");
  if (!request.handling.empty() && !lines_file) throw ArgError("--handling is for --kind pick --lines");
  const bool loader = request.handling == "loader";
  if (move && !to) throw ArgError("order add --kind move needs --to PLACE (a parking place)");
  if (lines_file && !to && !loader) {
    throw ArgError("order add --kind pick --lines needs --to PLACE (where the boxes go), or --handling loader");
  }
  if (!move && !lines_file && (!from || !to)) throw ArgError("order add needs --from AREA and --to AREA");
  request.pick_area = lines_file ? lines.front().place : from.value_or("");
  request.drop_area = to.value_or("");
  const long priority = args.integer("priority").value_or(0);
  request.priority = static_cast<int>(priority);
  request.robot_id = args.value("robot").value_or("");
  request.fleet_id = args.value("fleet").value_or("");
  const bool wait = args.flag("wait");

  FleetClient client(connection.domain);
  const model::ServerInfo info = require_server(client, connection);
  // The check the server and the web API make too; a name it refuses is bad input (exit 2).
  // The fleets and their abilities from the configuration, the place heights from the site the
  // server serves, the place names from the server itself.
  const auto site = map::load_site_map(known_site_path(command.source_dir, info.site));
  // The fleets of the site the server serves, unless named: a plant's pickers are not in the
  // default configuration.
  const auto config =
      config::load_fleet_config(command.config_given ? command.config_file : config_path_for(std::nullopt, info.site));
  orders::KnownNames names = traffic::order_request_names(config, site);
  names.areas = info.loading_areas;
  names.homes = info.homes;
  names.robots = info.robots;
  const std::map<std::string, std::string> flag_of{{"kind", "--kind"},   {"from", "--from"},
                                                   {"to", "--to"},       {"robot", "--robot"},
                                                   {"fleet", "--fleet"}, {"priority", "--priority"}};
  if (const auto problem = orders::check_order_request(
          {request.kind, request.pick_area, request.drop_area, request.robot_id, request.fleet_id, priority, loader},
          names)) {
    throw ArgError((lines_file && problem->field == "from" ? std::string("--lines") : flag_of.at(problem->field)) +
                   ": " + problem->message);
  }
  if (lines_file) {
    // What the site declares on its places; what is left of it now the server checks.
    if (const auto why = orders::check_pick_lines(lines, site.site.area_ids(), orders::declared_boxes(site.site),
                                                  orders::max_pickable_mass(config), *lines_file)) {
      throw ArgError(*why);
    }
    const auto poses = orders::place_poses(site.site);
    if (const auto tours = orders::plan_tours(lines, orders::kTourBoxes, poses).size(); wait && tours > 1 && !loader) {
      throw ArgError("--wait follows one order; these lines make " + std::to_string(tours) + " tours of at most " +
                     std::to_string(orders::kTourBoxes) + " boxes");
    }
  }

  const auto reply = client.request_order(request, connection.timeout);
  if (!reply) {
    throw CommandExit{kExitNoServer, "fleet-server on DDS domain " + std::to_string(connection.domain) +
                                         " did not answer the order request"};
  }
  // The request was well formed: a refusal is the fleet's (pallets, busy robots), not bad input.
  if (!reply->accepted) throw CommandExit{kExitFailed, "order refused: " + reply->error};
  const int created = std::max(1, reply->order_count);
  if (command.json && !wait) {
    nlohmann::json ids = nlohmann::json::array();
    for (int k = 0; k < created; ++k) ids.push_back(reply->order_id + k);
    out << nlohmann::json{{"order_id", reply->order_id}, {"order_ids", ids}, {"state", "QUEUED"}}.dump() << "\n";
  } else if (!command.json) {
    for (int k = 0; k < created; ++k) out << reply->order_id + k << "\n";
    out << std::flush;
  }
  if (!wait) return kExitOk;

  // Sim seconds, as order watch counts them.
  const SimClock clock(info.time_scale);
  const double started = clock.now();
  const auto limit = connection.timeout_given ? connection.timeout : FleetClient::kNoTimeout;
  const auto final_info = client.follow_order(
      reply->order_id,
      [&](const model::OrderInfo& o) {
        if (command.json) return;
        std::ostringstream line;
        line << std::fixed << std::setprecision(1) << "[" << clock.now() - started << " s sim] order " << o.order_id
             << " " << o.state;
        if (o.state == "ACTIVE" && !o.phase.empty()) line << " " << o.phase;
        if (!o.robot_id.empty()) line << " on " << o.robot_id;
        if (!o.reason.empty()) line << ": " << o.reason;
        err << line.str() << "\n";
      },
      limit);
  if (!final_info && client.server_alive()) {
    throw CommandExit{kExitFailed, "order " + std::to_string(reply->order_id) + " had not ended within --timeout"};
  }
  if (!final_info) {
    throw CommandExit{kExitNoServer, "fleet-server on DDS domain " + std::to_string(connection.domain) +
                                         " went away while order " + std::to_string(reply->order_id) + " was open"};
  }
  if (command.json) out << order_json(*final_info).dump() << "\n";
  return final_info->state == "DONE" ? kExitOk : kExitFailed;
}

std::string one_positional(const CommandFlags& args, const std::string& what) {
  const auto rest = args.positionals();
  if (rest.size() != 1) throw ArgError("expected exactly one " + what);
  return rest[0];
}

/// Sends a command and turns the server's answer into an exit code: refused for bad input (an
/// unknown name) is 2, refused because of the current state (an order already ended) is 1.
int run_command_on_server(FleetClient& client, const Connection& connection, model::Command command,
                          const CommandArgs& args, std::ostream& out, const std::string& done_message,
                          const nlohmann::json& done_json) {
  const auto reply = client.send_command(std::move(command), connection.timeout);
  if (!reply) {
    throw CommandExit{kExitNoServer, "fleet-server on DDS domain " + std::to_string(connection.domain) +
                                         " did not answer the command"};
  }
  if (!reply->accepted) {
    const bool bad_input = reply->error.rfind("unknown", 0) == 0 || reply->error.find("is not") != std::string::npos;
    throw CommandExit{bad_input ? kExitBadInput : kExitFailed, reply->error};
  }
  out << (args.json ? done_json.dump() : done_message) << "\n";
  return kExitOk;
}

int order_list(const CommandFlags& args, const CommandArgs& command, const Connection& connection, std::ostream& out) {
  const auto state = args.value("state");
  FleetClient client(connection.domain);
  require_server(client, connection);
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& [id, o] : client.orders(std::chrono::milliseconds(600))) {
    if (!state || o.state == *state) rows.push_back(order_json(o));
  }
  if (command.json) {
    out << rows.dump() << "\n";
    return kExitOk;
  }
  out << std::left << std::setw(7) << "ORDER" << std::setw(10) << "KIND" << std::setw(6) << "FROM" << std::setw(6)
      << "TO" << std::setw(7) << "ROBOT" << std::setw(11) << "STATE" << std::setw(11) << "PHASE"
      << "REASON\n";
  for (const auto& r : rows) {
    out << std::left << std::setw(7) << r["order_id"].get<long>() << std::setw(10) << r["kind"].get<std::string>()
        << std::setw(6) << r["pick_area"].get<std::string>() << std::setw(6) << r["drop_area"].get<std::string>()
        << std::setw(7) << r["robot_id"].get<std::string>() << std::setw(11) << r["state"].get<std::string>()
        << std::setw(11) << r["phase"].get<std::string>() << r["reason"].get<std::string>() << "\n";
  }
  return kExitOk;
}

int order_show(const CommandFlags& args, const CommandArgs& command, const Connection& connection, std::ostream& out) {
  const std::int64_t id = order_id_of(one_positional(args, "order id"));
  FleetClient client(connection.domain);
  require_server(client, connection);
  const auto orders = client.orders(std::chrono::milliseconds(600));
  const auto it = orders.find(id);
  if (it == orders.end()) throw CommandExit{kExitBadInput, "unknown order " + std::to_string(id)};
  nlohmann::json o = order_json(it->second);
  // The chain onwards: the orders that follow from this one (the packing chain's transports).
  std::vector<const model::OrderInfo*> led_to;
  for (const auto& [other_id, other] : orders) {
    if (std::find(other.caused_by.begin(), other.caused_by.end(), id) != other.caused_by.end())
      led_to.push_back(&other);
  }
  o["led_to"] = nlohmann::json::array();
  for (const auto* next : led_to) o["led_to"].push_back(next->order_id);
  if (command.json) {
    out << o.dump() << "\n";
    return kExitOk;
  }
  out << "order " << id << ": " << o["pick_area"].get<std::string>() << " -> " << o["drop_area"].get<std::string>()
      << ", " << o["state"].get<std::string>()
      << (o["robot_id"].get<std::string>().empty() ? "" : " on " + o["robot_id"].get<std::string>()) << "\n";
  if (!it->second.cause.empty()) out << "  because " << it->second.cause << "\n";
  for (const auto* next : led_to) {
    out << "  led to order " << next->order_id << ": " << next->pick_area << " -> " << next->drop_area << ", "
        << next->state << (next->cause.empty() ? "" : " (" + next->cause + ")") << "\n";
  }
  const double created = it->second.created_sim;
  for (const auto& e : it->second.history) {
    out << std::fixed << std::setprecision(1) << "  +" << e.sim_time - created << " s  " << e.state
        << (e.phase.empty() ? "" : " " + e.phase) << (e.robot_id.empty() ? "" : " " + e.robot_id)
        << (e.reason.empty() ? "" : "  (" + e.reason + ")") << "\n";
  }
  return kExitOk;
}

int order_cancel(const CommandFlags& args, const CommandArgs& command, const Connection& connection,
                 std::ostream& out) {
  const std::int64_t id = order_id_of(one_positional(args, "order id"));
  FleetClient client(connection.domain);
  require_server(client, connection);
  model::Command c;
  c.verb = "cancel-order";
  c.target = std::to_string(id);
  return run_command_on_server(client, connection, c, command, out, "order " + std::to_string(id) + " cancelled",
                               {{"order_id", id}, {"state", "CANCELLED"}});
}

}  // namespace

int obstacle_command(const CommandArgs& command, const Connection& connection, std::ostream& out, std::ostream& err) {
  try {
    // list, on and off are subcommands of the table, whose flags (none) main() has checked.
    const std::vector<std::string>& words = command.args;
    const std::string sub = words.empty() ? "" : words[0];
    FleetClient client(connection.domain);
    if (sub == "list" && words.size() == 1) {
      const model::ServerInfo info = require_server(client, connection);
      const auto states = client.obstacles(std::chrono::milliseconds(600));
      nlohmann::json rows = nlohmann::json::array();
      for (const auto& id : info.obstacles) {
        const auto it = states.find(id);
        rows.push_back({{"obstacle_id", id}, {"enabled", it != states.end() && it->second.enabled}});
      }
      if (command.json) {
        out << rows.dump() << "\n";
      } else {
        for (const auto& r : rows)
          out << r["obstacle_id"].get<std::string>() << "  " << (r["enabled"].get<bool>() ? "on" : "off") << "\n";
      }
      return kExitOk;
    }
    if ((sub == "on" || sub == "off") && words.size() == 2) {
      const model::ServerInfo info = require_server(client, connection);
      require_known("obstacle", words[1], info.obstacles);
      model::Command c;
      c.verb = "obstacle";
      c.target = words[1];
      c.value = sub;
      return run_command_on_server(client, connection, c, command, out, "obstacle " + words[1] + " " + sub,
                                   {{"obstacle_id", words[1]}, {"enabled", sub == "on"}});
    }
    throw ArgError("usage: obstacle list | obstacle on ID | obstacle off ID");
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

int robot_control_command(const std::string& verb, const CommandArgs& command, const Connection& connection,
                          std::ostream& out, std::ostream& err) {
  try {
    const CommandFlags args(verb, "", command.args);
    const std::string robot = one_positional(args, "robot id");
    FleetClient client(connection.domain);
    const model::ServerInfo info = require_server(client, connection);
    require_known("robot", robot, info.robots);
    model::Command c;
    c.verb = verb;
    c.target = robot;
    return run_command_on_server(client, connection, c, command, out, "robot " + robot + " " + verb + "d",
                                 {{"robot_id", robot}, {"paused", verb == "pause"}});
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

int auto_orders_command(const CommandArgs& command, const Connection& connection, std::ostream& out,
                        std::ostream& err) {
  try {
    // on and off are subcommands of the table, whose flags (none) main() has checked.
    const std::string value = command.args.empty() ? std::string() : command.args.front();
    if (command.args.size() != 1 || (value != "on" && value != "off")) {
      throw ArgError("auto-orders takes on or off" + (value.empty() ? std::string() : ", got '" + value + "'"));
    }
    FleetClient client(connection.domain);
    require_server(client, connection);
    model::Command c;
    c.verb = "auto-orders";
    c.value = value;
    return run_command_on_server(client, connection, c, command, out, "automatic orders " + value,
                                 {{"auto_orders", value == "on"}});
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

int map_list_command(const CommandArgs& command, const Connection& connection, std::ostream& out, std::ostream& err) {
  try {
    // main() sends only map list and map set here.
    const std::string& sub = command.args.front();
    const CommandFlags args("map", sub, std::vector<std::string>(command.args.begin() + 1, command.args.end()));
    if (sub == "set") {
      // map set MAP [--robot R]: every robot (or one, with traffic off) onto another map of the site.
      const std::string map_id = one_positional(args, "map id");
      const auto robot = args.value("robot");
      FleetClient client(connection.domain);
      const model::ServerInfo info = require_server(client, connection);
      require_known("map", map_id, info.maps);
      if (robot) require_known("robot", *robot, info.robots);
      model::Command c;
      c.verb = "map";
      c.target = robot.value_or("");
      c.value = map_id;
      return run_command_on_server(client, connection, c, command, out,
                                   (robot ? "robot " + *robot : std::string("every robot")) + " on map " + map_id,
                                   {{"map", map_id}, {"robot_id", robot.value_or("")}});
    }
    FleetClient client(connection.domain);
    const model::ServerInfo info = require_server(client, connection);
    if (command.json) {
      out << nlohmann::json{{"site", info.site}, {"maps", info.maps}}.dump() << "\n";
    } else {
      for (const auto& m : info.maps) out << m << (m == info.site ? "  (served)" : "") << "\n";
    }
    return kExitOk;
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

int order_command(const CommandArgs& command, const Connection& connection, std::ostream& out, std::ostream& err) {
  try {
    const std::string sub = command.args.empty() ? std::string() : command.args.front();
    const std::vector<std::string> rest(command.args.begin() + (sub.empty() ? 0 : 1), command.args.end());
    if (sub == "watch") return order_watch(rest, command, connection, out, err);
    if (find_command("order", sub) != nullptr) {
      const CommandFlags flags("order", sub, rest);
      if (sub == "add") return order_add(flags, command, connection, out, err);
      if (sub == "list") return order_list(flags, command, connection, out);
      if (sub == "show") return order_show(flags, command, connection, out);
      if (sub == "cancel") return order_cancel(flags, command, connection, out);
    }
    throw ArgError(sub.empty() ? "order needs a subcommand: add, list, show, cancel, watch"
                               : "unknown order subcommand '" + sub + "' (add, list, show, cancel, watch)");
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

int stats_command(const CommandArgs& command, const Connection& connection, std::ostream& out, std::ostream& err) {
  try {
    const CommandFlags args("stats", "", command.args);
    FleetClient client(connection.domain);
    const model::ServerInfo info = require_server(client, connection);
    const auto orders = client.orders(std::chrono::milliseconds(600));
    const monitor::OrderStats s = monitor::order_stats(orders, SimClock(info.time_scale).now());
    nlohmann::json utilisation = nlohmann::json::object();
    for (const auto& [robot, share] : s.utilisation) utilisation[robot] = share;
    const nlohmann::json doc{{"orders_by_state", s.by_state},           {"span_s", s.span_s},
                             {"done_per_hour", s.done_per_hour},        {"order_time_mean_s", s.order_time_mean_s},
                             {"order_time_p95_s", s.order_time_p95_s},  {"utilisation", utilisation},
                             {"refused_samples", info.refused_samples}, {"refused_senders", info.refused_senders}};
    if (command.json) {
      out << doc.dump() << "\n";
      return kExitOk;
    }
    out << std::fixed << std::setprecision(1) << "orders:";
    for (const auto& [state, n] : s.by_state) out << " " << state << " " << n;
    out << "\ndone per hour: " << s.done_per_hour << " (over " << s.span_s << " s sim)\n"
        << "order time: mean " << s.order_time_mean_s << " s, p95 " << s.order_time_p95_s << " s (sim)\n"
        << "utilisation:";
    for (const auto& [robot, share] : s.utilisation) out << " " << robot << " " << 100.0 * share << " %";
    out << "\nrefused samples: " << info.refused_samples << " (robots' messages from writers that may not speak "
        << "for the robot they name)\n";
    for (const std::string& sender : info.refused_senders) out << "  " << sender << "\n";
    return kExitOk;
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

int routing_age_command(const CommandArgs& command, const Connection& connection, std::ostream& out,
                        std::ostream& err) {
  // [Forklift thesis, section 3]: poses reach the other robots through the server. Each pose's age on
  // arrival here (now minus the sim time it was measured at) is sampled twice: straight from the
  // robot (RobotState) and as routed by the server (FleetView). The difference is what routing
  // costs; both share this process's scheduling, so it cancels out of the comparison.
  try {
    const CommandFlags args("routing-age", "", command.args);
    const double seconds = args.number("seconds").value_or(10.0);
    FleetClient client(connection.domain);
    const model::ServerInfo info = require_server(client, connection);
    const SimClock clock(info.time_scale);
    dds::Participant& participant = client.participant();
    dds::Reader<model::RobotState> direct(participant, dds::qos::live_state(), dds::robot_report_partitions());
    dds::Reader<model::FleetView> routed(participant, dds::qos::live_state());
    std::vector<double> direct_ms, routed_ms;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      direct.take_data(
          [&](model::RobotState&& s) { direct_ms.push_back(1000.0 * clock.to_wall(clock.now() - s.sim_time)); });
      routed.take_data([&](model::FleetView&& v) {
        const double now = clock.now();
        for (const auto& r : v.robots) routed_ms.push_back(1000.0 * clock.to_wall(now - r.sim_time));
      });
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (direct_ms.empty() || routed_ms.empty()) {
      throw CommandExit{kExitFailed, "no robot poses on DDS domain " + std::to_string(connection.domain) + " within " +
                                         std::to_string(seconds) + " s"};
    }
    const double d50 = common::percentile(direct_ms, 0.5), d95 = common::percentile(direct_ms, 0.95);
    const double r50 = common::percentile(routed_ms, 0.5), r95 = common::percentile(routed_ms, 0.95);
    const nlohmann::json doc{{"direct_samples", direct_ms.size()},  {"routed_samples", routed_ms.size()},
                             {"direct_age_median_ms", d50},         {"direct_age_p95_ms", d95},
                             {"routed_age_median_ms", r50},         {"routed_age_p95_ms", r95},
                             {"routing_adds_median_ms", r50 - d50}, {"routing_adds_p95_ms", r95 - d95},
                             {"time_scale", info.time_scale}};
    if (command.json) {
      out << doc.dump() << "\n";
    } else {
      out << std::fixed << std::setprecision(1) << "pose age on arrival, wall ms (median / p95):\n"
          << "  direct RobotState:  " << d50 << " / " << d95 << "  (" << direct_ms.size() << " samples)\n"
          << "  routed FleetView:   " << r50 << " / " << r95 << "  (" << routed_ms.size() << " samples)\n"
          << "  routing adds:       " << r50 - d50 << " / " << r95 - d95 << "\n";
    }
    return kExitOk;
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

int robots_command(const CommandArgs& command, const Connection& connection, std::ostream& out, std::ostream& err) {
  try {
    const CommandFlags args("robots", "", command.args);
    const bool all = args.flag("all");
    FleetClient client(connection.domain);
    const model::ServerInfo info = require_server(client, connection);
    const auto states = client.robot_states(std::chrono::milliseconds(600));
    const SimClock clock(info.time_scale);
    // Vehicles of other makers, driven over VDA 5050: their maker and serial number, from the
    // configuration fleetctl reads (the server's when both read the same file).
    std::map<std::string, std::string> vda5050_of;
    try {
      const config::FleetConfig config = config::load_fleet_config(command.config_file);
      for (const auto& [fleet, robot] : config.all_robots()) {
        if (fleet->vda5050) vda5050_of[robot->id] = fleet->vda5050->manufacturer + " " + robot->serial_number;
      }
    } catch (const std::exception&) {
      // Without a readable configuration the robots are listed unmarked.
    }
    nlohmann::json rows = nlohmann::json::array();
    std::vector<std::string> not_seen;
    for (const auto& id : info.robots) {
      auto it = states.find(id);
      if (it == states.end()) {
        // Configured robots without an agent are listed only on request: a 4-robot demo of a
        // 12-robot configuration is four rows.
        not_seen.push_back(id);
        if (all) rows.push_back({{"robot_id", id}, {"health", "not seen"}});
        continue;
      }
      const auto& s = it->second;
      rows.push_back({{"robot_id", id},
                      {"fleet_id", s.fleet_id},
                      {"state", s.task_state},
                      {"x", s.pose.x},
                      {"y", s.pose.y},
                      {"yaw", s.pose.yaw},
                      {"order_id", s.order_id},
                      {"carrying_pallet", s.carrying_pallet},
                      {"localization_score", s.localization_score},
                      {"age_s", std::max(0.0, clock.now() - s.sim_time)},
                      {"health", "alive"}});
      if (const auto v = vda5050_of.find(id); v != vda5050_of.end()) {
        rows.back()["vda5050"] = v->second;
        rows.back()["detail"] = s.detail;
      }
    }
    if (command.json) {
      out << rows.dump() << "\n";
      return kExitOk;
    }
    out << std::left << std::setw(8) << "ROBOT" << std::setw(14) << "FLEET" << std::setw(15) << "STATE" << std::setw(24)
        << "POSE (x, y, yaw)" << std::setw(7) << "ORDER" << std::setw(7) << "LOC"
        << "HEALTH\n";
    for (const auto& r : rows) {
      std::ostringstream pose, order, loc;
      if (r.contains("x")) {
        pose << std::fixed << std::setprecision(2) << r["x"].get<double>() << ", " << r["y"].get<double>() << ", "
             << r["yaw"].get<double>();
        order << (r["order_id"].get<long>() ? std::to_string(r["order_id"].get<long>()) : "-");
        loc << std::fixed << std::setprecision(2) << r["localization_score"].get<double>();
      }
      out << std::left << std::setw(8) << r["robot_id"].get<std::string>() << std::setw(14) << r.value("fleet_id", "-")
          << std::setw(15) << r.value("state", "-") << std::setw(24) << pose.str() << std::setw(7) << order.str()
          << std::setw(7) << loc.str() << r["health"].get<std::string>();
      if (r.contains("vda5050")) {
        out << "  VDA 5050 " << r["vda5050"].get<std::string>();
        if (!r.value("detail", "").empty()) out << ": " << r["detail"].get<std::string>();
      }
      out << "\n";
    }
    if (rows.empty()) out << "no robot has reported to this server\n";
    if (!all && !not_seen.empty()) {
      out << not_seen.size() << " configured robot" << (not_seen.size() == 1 ? " has" : "s have")
          << " not reported (--all lists them): " << model::join(not_seen) << "\n";
    }
    return kExitOk;
  } catch (const CommandExit& e) {
    return report_failure(command.json, e.code, e.message, out, err);
  }
}

}  // namespace fleet::cli
