// fleetctl: the Fleet command line. Orders, robots, the demo, and offline evaluation tools.

#include <iostream>
#include <map>

#include "cli/commands.hpp"
#include "cli/fleet_run.hpp"
#include "cli/online_commands.hpp"
#include "common/args.hpp"
#include "common/paths.hpp"
#include "config/fleet_config.hpp"
#include "config/schema.hpp"
#include "dds/environment.hpp"
#include "map/site.hpp"

namespace {

constexpr const char* kHelp = R"(usage: fleetctl [global flags] COMMAND [flags]

Drive a Fleet from the terminal or from scripts. fleetctl is a DDS participant of its own.

commands (need a running fleet-server):
  order add --from AREA --to AREA [--priority P] [--robot R] [--fleet F] [--wait]
                       create a transport order, print its id; --wait follows it to its end
  order list [--state S] | order show ID | order cancel ID
                       the orders the server knows, one with its history, cancel one
  obstacle list | obstacle on ID | obstacle off ID
                       the designated static obstacles and switching them
  pause ROBOT | resume ROBOT
                       stop a robot where it is, and let it go on
  map list             the maps the server knows, and the one it serves
  robots               table of robots: fleet, state, pose, order, localization score, health
  stats                orders by state, done per hour, mean and p95 order time, robot utilisation
  routing-age [--seconds S=10]
                       a pose's age on arrival, straight from the robot vs routed by the server

commands that start a fleet:
  demo [--agents N=4] [--site NAME] [--duration SECONDS] [--time-scale K] [--seed S] [--http-port P=8080]
                       one fleet-server and N fleet-agents with automatic orders; Ctrl-C or
                       --duration (wall seconds) stops them all and prints a summary; the
                       web view's address (with its token) is printed at start

offline tools (core libraries only, no DDS):
  map check SITE.yaml | map sample FILE.xodr [--step M] | map render SITE.yaml -o FILE.svg
  loc-eval [--trajectory square|figure8|table_a_loop] [--duration S] [--seed N] [--nlos F] [--plot FILE.svg]
  plan-eval --site NAME [--queries N] [--seed S]
  ctrl-eval [--seed S] [--runs N] [--site NAME] [--speed V] [--follower seed|regulated] [--gyro-cal] [--plot F.svg]
  config keys          every configuration key with default, unit, range and meaning

global flags:
  --domain N           DDS domain id (default: dds.domain of the configuration)
  --json               machine-readable output: one JSON document (the last line printed)
  --timeout S          seconds to look for the server (default 3)
  --config FILE        configuration (default: config/fleet.yaml)
  --help               this text

exit codes:
  0  ok
  1  the operation ran and failed (order FAILED or CANCELLED, a run lost orders)
  2  bad input (unknown area, robot or key; malformed file; bad flag)
  3  no fleet-server reachable on the DDS domain
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace fleet;
  using namespace fleet::cli;
  std::ostream& out = std::cout;
  std::ostream& err = std::cerr;
  try {
    Args args(argc, argv);
    CommandArgs command;
    command.json = args.flag("json");
    command.config_file = args.value("config").value_or(default_config_path());
    command.source_dir = project_root();
    const auto domain_flag = args.integer("domain", 0, 232);
    const double timeout_s = args.number("timeout", 0.1, 3600.0).value_or(3.0);
    const bool help = args.flag("help");
    if (help || args.remaining().empty()) {
      out << kHelp;
      return help ? kExitOk : kExitBadInput;
    }
    const std::string name = args.remaining().front();
    command.args.assign(args.remaining().begin() + 1, args.remaining().end());

    // Offline tools need no configuration or DDS (`map list` asks the server).
    const bool map_list = name == "map" && !command.args.empty() && command.args[0] == "list";
    if (name == "map" && !map_list) return map_command(command, out, err);
    if (name == "loc-eval") return loc_eval_command(command, out, err);
    if (name == "plan-eval") return plan_eval_command(command, out, err);
    if (name == "ctrl-eval") return ctrl_eval_command(command, out, err);
    if (name == "config") {
      if (command.args.size() == 1 && command.args[0] == "keys") {
        out << config::schema_markdown();
        return kExitOk;
      }
      throw ArgError("config needs a subcommand: keys");
    }

    const config::FleetConfig config = config::load_fleet_config(command.config_file);
    Connection connection;
    connection.domain = static_cast<std::uint32_t>(domain_flag.value_or(config.settings.get_int("dds.domain")));
    connection.timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
    dds::use_fleet_dds_config();

    if (name == "order") return order_command(command, connection, out, err);
    if (name == "robots") return robots_command(command, connection, out, err);
    if (name == "stats") return stats_command(command, connection, out, err);
    if (name == "obstacle") return obstacle_command(command, connection, out, err);
    if (name == "pause" || name == "resume") return robot_control_command(name, command, connection, out, err);
    if (map_list) return map_list_command(command, connection, out, err);
    if (name == "routing-age") return routing_age_command(command, connection, out, err);
    if (name == "demo") return demo_command(command, out, err, connection.domain);
    throw ArgError("unknown command '" + name + "'; see fleetctl --help");
  } catch (const InputError& e) {
    err << "fleetctl: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    err << "fleetctl: " << e.what() << "\n";
    return kExitFailed;
  }
}
