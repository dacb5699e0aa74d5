#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace fleet::cli {

/// Exit codes of every fleetctl command (documented in --help and the README).
enum ExitCode : int {
  kExitOk = 0,        ///< the operation succeeded
  kExitFailed = 1,    ///< the operation ran and failed (order FAILED, target missed, ...)
  kExitBadInput = 2,  ///< bad input: unknown area, malformed file, bad flag
  kExitNoServer = 3,  ///< no fleet-server reachable
};

/// Arguments of one subcommand: everything after the subcommand name, global flags removed.
struct CommandArgs {
  std::vector<std::string> args;
  bool json = false;          ///< --json: the last line printed is one JSON object
  std::string config_file;    ///< --config, default config/fleet.yaml
  bool config_given = false;  ///< --config or --site named the configuration
  std::string source_dir;     ///< project root (maps/, config/ live there)
};

/// The site files' names under `source_dir`/maps (without .yaml), sorted.
std::vector<std::string> site_names(const std::string& source_dir);
/// maps/NAME.yaml under `source_dir`; InputError naming NAME and listing the sites there when it
/// does not exist.
std::string known_site_path(const std::string& source_dir, const std::string& name);

// Offline subcommands working on core/ alone. Each returns an ExitCode and prints results to
// `out`, errors to `err`.
int map_command(const CommandArgs& args, std::ostream& out, std::ostream& err);       // map check|sample|render
int loc_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err);  // loc-eval
/// loc-eval --trajectory rack_aisle|plant_route: the picker's localization by markers.
int marker_loc_eval_command(const CommandArgs& args, const std::string& trajectory, double duration, std::uint64_t seed,
                            bool json, std::ostream& out, std::ostream& err);
int plan_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err);     // plan-eval
int ctrl_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err);     // ctrl-eval
int fleets_command(const CommandArgs& args, std::ostream& out, std::ostream& err);        // fleets
int dock_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err);     // dock-eval
int pick_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err);     // pick-eval
int traffic_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err);  // traffic-eval
int mapf_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err);     // mapf-eval
int security_command(const CommandArgs& args, std::ostream& out, std::ostream& err);      // security init|check

}  // namespace fleet::cli
