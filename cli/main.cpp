// fleetctl: the Fleet command line. Orders, robots, the demo, and offline evaluation tools.

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "app/process.hpp"
#include "cli/command_flags.hpp"
#include "cli/command_table.hpp"
#include "cli/commands.hpp"
#include "cli/fleet_run.hpp"
#include "cli/online_commands.hpp"
#include "cli/online_support.hpp"
#include "common/args.hpp"
#include "common/paths.hpp"
#include "config/fleet_config.hpp"
#include "config/schema.hpp"
#include "dds/environment.hpp"
#include "map/site.hpp"
#include "model/names.hpp"

namespace {

/// `config keys --json`: the schema as data.
nlohmann::json schema_json() {
  nlohmann::json keys = nlohmann::json::array();
  for (const auto& key : fleet::config::schema()) {
    static const char* const kTypes[] = {"double", "int", "bool", "string", "choice"};
    nlohmann::json entry{{"key", key.key},
                         {"type", kTypes[static_cast<int>(key.type)]},
                         {"default", key.default_value},
                         {"unit", key.unit},
                         {"description", key.description}};
    if (key.type == fleet::config::ValueType::kDouble || key.type == fleet::config::ValueType::kInt) {
      entry["min"] = key.min;
      entry["max"] = key.max;
    }
    if (key.type == fleet::config::ValueType::kChoice) entry["choices"] = key.choices;
    keys.push_back(entry);
  }
  return keys;
}

/// Every flag given to a command must be declared in its entry of the command table, with a value
/// of the declared type, range and choices (CommandFlags); a command with subcommands is checked
/// once its subcommand is known (an unknown one is the command's own message).
void check_flags(const std::string& name, const std::vector<std::string>& args) {
  using fleet::cli::CommandSpec;
  const auto check = [&](const CommandSpec& spec, const std::vector<std::string>& flags) {
    try {
      fleet::cli::CommandFlags(spec, flags);
    } catch (const fleet::ArgError& e) {
      throw fleet::ArgError(name + ": " + e.what() + "\nusage: fleetctl " + fleet::cli::usage_line(spec));
    }
  };
  if (const CommandSpec* spec = fleet::cli::find_command(name, "")) {
    check(*spec, args);
  } else if (!args.empty()) {
    if (const CommandSpec* sub = fleet::cli::find_command(name, args.front())) {
      check(*sub, std::vector<std::string>(args.begin() + 1, args.end()));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace fleet;
  using namespace fleet::cli;
  std::ostream& out = std::cout;
  std::ostream& err = std::cerr;
  // Known before anything can fail, so that every error honours --json.
  const bool json_output = std::any_of(argv + 1, argv + argc, [](const char* a) { return std::string(a) == "--json"; });
  try {
    Args args(argc, argv);
    CommandArgs command;
    command.json = args.flag("json");
    // A site with fleets of its own (config/sites/SITE.yaml) brings them when no --config is given.
    const auto config_flag = args.value("config");
    const auto site_flag = args.peek("site");
    command.config_file = config_path_for(config_flag, site_flag);
    command.config_given = config_flag.has_value() || site_flag.has_value();
    command.source_dir = project_root();
    const auto domain_flag = args.integer("domain", 0, 232);
    const auto security_flag = args.value("security");
    const auto timeout_flag = args.number("timeout", 0.1, 1e6);
    const double timeout_s = timeout_flag.value_or(3.0);
    const bool help = args.flag("help");
    if (help || args.remaining().empty()) {
      out << help_text();
      return help ? kExitOk : kExitBadInput;
    }
    const std::string name = args.remaining().front();
    command.args.assign(args.remaining().begin() + 1, args.remaining().end());
    check_flags(name, command.args);

    // Offline tools need no configuration or DDS (`map list` asks the server).
    // map list and map set talk to the server; map check, sample and render read files.
    const bool map_list =
        name == "map" && !command.args.empty() && (command.args[0] == "list" || command.args[0] == "set");
    if (name == "map" && !map_list) return map_command(command, out, err);
    if (name == "loc-eval") return loc_eval_command(command, out, err);
    if (name == "plan-eval") return plan_eval_command(command, out, err);
    if (name == "ctrl-eval") return ctrl_eval_command(command, out, err);
    if (name == "dock-eval") return dock_eval_command(command, out, err);
    if (name == "pick-eval") return pick_eval_command(command, out, err);
    if (name == "fleets") return fleets_command(command, out, err);
    if (name == "traffic-eval") return traffic_eval_command(command, out, err);
    if (name == "mapf-eval") return mapf_eval_command(command, out, err);
    if (name == "security") return security_command(command, out, err);
    if (name == "config") {
      if (!command.args.empty() && command.args[0] == "keys") {
        const CommandFlags keys("config", "keys",
                                std::vector<std::string>(command.args.begin() + 1, command.args.end()));
        const bool markdown = keys.flag("markdown");
        if (markdown) {
          out << config::configuration_page();
          return kExitOk;
        }
        out << (command.json ? schema_json().dump() + "\n" : config::schema_markdown());
        return kExitOk;
      }
      throw ArgError("config needs a subcommand: keys");
    }
    if (name == "completion") {
      if (command.args.size() == 1 && command.args[0] == "bash") {
        const std::string script = bash_completion_script();
        if (command.json) {
          nlohmann::json doc = command_table_json();
          doc["shell"] = "bash";
          doc["script"] = script;
          out << doc.dump() << "\n";
        } else {
          out << script;
        }
        return kExitOk;
      }
      throw ArgError("completion needs a shell: bash (load it with: source <(fleetctl completion bash))");
    }
    if (const auto names = command_names(); std::find(names.begin(), names.end(), name) == names.end()) {
      throw ArgError(model::unknown_name_message("command", name, names) + "; see fleetctl --help");
    }

    const config::FleetConfig config = config::load_fleet_config(command.config_file);
    Connection connection;
    connection.domain = static_cast<std::uint32_t>(domain_flag.value_or(config.settings.get_int("dds.domain")));
    connection.timeout = std::chrono::milliseconds(static_cast<long>(timeout_s * 1000));
    connection.timeout_given = timeout_flag.has_value();
    dds::use_fleet_dds_config();
    // The operator's credentials for this process; demo and soak hand each process its own.
    app::use_dds_security(security_flag.value_or(config.settings.get_string("dds.security")), "operator",
                          security_flag ? "--security" : "dds.security");

    if (name == "order") return order_command(command, connection, out, err);
    if (name == "robots") return robots_command(command, connection, out, err);
    if (name == "traffic") return traffic_show_command(command, connection, out, err);
    if (name == "stats") return stats_command(command, connection, out, err);
    if (name == "servers") return servers_command(command, connection, out, err);
    if (name == "obstacle") return obstacle_command(command, connection, out, err);
    if (name == "pause" || name == "resume") return robot_control_command(name, command, connection, out, err);
    if (name == "auto-orders") return auto_orders_command(command, connection, out, err);
    if (map_list) return map_list_command(command, connection, out, err);
    if (name == "inject") return inject_command(command, connection, out, err);
    if (name == "routing-age") return routing_age_command(command, connection, out, err);
    if (name == "demo") return demo_command(command, out, err, connection.domain);
    if (name == "soak") return soak_command(command, out, err, connection.domain);
    if (name == "load") return load_command(command, out, err, connection.domain);
    throw ArgError("unknown command '" + name + "'; see fleetctl --help");
  } catch (...) {
    // The message without the program name, which report_failure adds.
    std::ostringstream message;
    const int code = app::exit_code_of_current_exception("", message, false);
    std::string text = message.str();
    if (text.starts_with(": ")) text.erase(0, 2);
    while (!text.empty() && text.back() == '\n') text.pop_back();
    return cli::report_failure(json_output, code, text, out, err);
  }
}
