#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace fleet::cli {

/// One flag of a command, as --help shows it and the shell completes it.
struct FlagSpec {
  enum class Kind { kSwitch, kValue, kFile, kChoice };
  /// What a value must parse as (CommandFlags checks it): text, an integer or a finite number
  /// within [min, max], or a non-negative integer of the whole 64-bit range (seeds).
  enum class Type { kText, kInteger, kNumber, kUnsigned };
  std::string name;  ///< with its dashes: "--from", "-o"
  Kind kind = Kind::kSwitch;
  std::string hint;                  ///< what the value is: "AREA", "N/min"; empty for a switch
  std::vector<std::string> choices;  ///< for Kind::kChoice; completed and shown as a|b|c
  bool required = false;
  Type type = Type::kText;
  double min = 0.0;
  double max = 0.0;
};

/// One command line fleetctl understands: a command, maybe a subcommand, its positional
/// arguments and flags. --help and the shell completion are both generated from the table of
/// these, so neither can forget a command.
struct CommandSpec {
  enum class Group { kServer, kStartsFleet, kOffline };
  Group group = Group::kServer;
  std::string command;            ///< "order"
  std::string subcommand;         ///< "add"; empty when the command has none
  std::string positionals;        ///< "ID", "[ID]", "SITE.yaml ..."; empty for none
  bool positional_files = false;  ///< the positionals are file names (completed as such)
  std::vector<FlagSpec> flags;
  std::string summary;  ///< one or more lines for --help
};

/// Every command, in the order --help lists them.
const std::vector<CommandSpec>& command_table();
/// The flags every command accepts (--domain, --json, --timeout, --config, --help).
const std::vector<FlagSpec>& global_flags();

/// "order add --from AREA --to AREA [--priority P] ..." for one entry.
std::string usage_line(const CommandSpec& spec);
/// The full --help text: every command, the global flags and the exit codes.
std::string help_text();
/// A bash completion script for fleetctl (commands, subcommands, flags, flag choices, files).
std::string bash_completion_script();
/// The command table as JSON, for tools that want to read it.
nlohmann::json command_table_json();

/// Every distinct command name, for "unknown command" messages.
std::vector<std::string> command_names();

}  // namespace fleet::cli
