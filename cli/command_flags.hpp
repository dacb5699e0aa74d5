#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/command_table.hpp"

namespace fleet::cli {

/// A command's arguments parsed against its entry of the command table, where each flag is
/// declared once (name, kind, value type, range, choices): what --help, the shell completion and
/// the docs test read too. An undeclared flag, a missing value, a value that is not of the flag's
/// type, out of its range or not among its choices, or an argument to a command that takes none,
/// is an ArgError naming it. Accepts
/// `--name value` and `--name=value`; a value flag given twice keeps every value (`values`).
class CommandFlags {
 public:
  CommandFlags(const CommandSpec& spec, const std::vector<std::string>& args);
  /// The entry of `command` (and `subcommand`, when the command has them) and `args` parsed by it.
  CommandFlags(std::string_view command, std::string_view subcommand, const std::vector<std::string>& args);

  /// Whether the switch --name was given. Reading a flag the entry does not declare, or as
  /// another type than declared, is a programming error (std::logic_error).
  bool flag(std::string_view name) const;
  /// The last value of --name; nothing when absent.
  std::optional<std::string> value(std::string_view name) const;
  /// Every value of a repeatable flag (--set), in order.
  std::vector<std::string> values(std::string_view name) const;
  std::optional<long> integer(std::string_view name) const;
  std::optional<double> number(std::string_view name) const;
  std::optional<std::uint64_t> u64(std::string_view name) const;
  /// The arguments that are no flag or flag value, in order.
  const std::vector<std::string>& positionals() const { return positionals_; }
  /// "usage: fleetctl <usage_line>\n".
  std::string usage() const;
  /// Whether -h asked for the usage (fleetctl takes --help itself, for all commands).
  bool asks_for_usage() const { return asks_for_usage_; }

 private:
  const FlagSpec& declared(std::string_view name, FlagSpec::Type type) const;

  const CommandSpec& spec_;
  std::map<std::string, std::vector<std::string>, std::less<>> given_;  ///< flag name with dashes -> its values
  std::vector<std::string> positionals_;
  bool asks_for_usage_ = false;
};

/// `args` parsed for `command` (and `subcommand`), or, when they are wrong, the error and the
/// command's usage on `err` and nothing: for commands that report bad input themselves.
std::optional<CommandFlags> flags_or_report(std::string_view command, std::string_view subcommand,
                                            const std::vector<std::string>& args, std::ostream& err);
inline std::optional<CommandFlags> flags_or_report(std::string_view command, const std::vector<std::string>& args,
                                                   std::ostream& err) {
  return flags_or_report(command, "", args, err);
}

/// `args` parsed for `command`, or nothing when the command ends here with `exit_code`: -h printed
/// its usage on `out` (kExitOk), or the flags were wrong and `err` says so with the usage
/// (kExitBadInput).
std::optional<CommandFlags> flags_or_exit(std::string_view command, const std::vector<std::string>& args,
                                          std::ostream& out, std::ostream& err, int& exit_code);

/// The command table's entry for `command` and `subcommand` ("" for a command without); for a
/// command with subcommands and an empty or unknown `subcommand`, nullptr.
const CommandSpec* find_command(std::string_view command, std::string_view subcommand);

}  // namespace fleet::cli
