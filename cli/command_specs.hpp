#pragma once

// The entries of fleetctl's command table, by group, and the helpers that write a flag's entry.

#include <string>
#include <utility>
#include <vector>

#include "cli/command_table.hpp"

namespace fleet::cli::specs {

using Kind = FlagSpec::Kind;
using Group = CommandSpec::Group;

inline FlagSpec value(std::string name, std::string hint, bool required = false) {
  return {std::move(name), Kind::kValue, std::move(hint), {}, required};
}
inline FlagSpec file(std::string name, std::string hint, bool required = false) {
  return {std::move(name), Kind::kFile, std::move(hint), {}, required};
}
inline FlagSpec choice(std::string name, std::vector<std::string> choices, std::string hint = "") {
  return {std::move(name), Kind::kChoice, std::move(hint), std::move(choices), false};
}
inline FlagSpec on_off(std::string name) {
  return {std::move(name), Kind::kSwitch, "", {}, false};
}
inline FlagSpec integer(std::string name, std::string hint, double min, double max) {
  FlagSpec f = value(std::move(name), std::move(hint));
  f.type = FlagSpec::Type::kInteger;
  f.min = min;
  f.max = max;
  return f;
}
inline FlagSpec number(std::string name, std::string hint, double min, double max) {
  FlagSpec f = integer(std::move(name), std::move(hint), min, max);
  f.type = FlagSpec::Type::kNumber;
  return f;
}
/// A seed of the whole 64-bit range.
inline FlagSpec seed() {
  FlagSpec f = value("--seed", "S");
  f.type = FlagSpec::Type::kUnsigned;
  return f;
}
/// The seed of a run of fleet processes: they take a 32-bit signed setting.
inline FlagSpec process_seed() {
  return integer("--seed", "S", 0, 2147483647);
}

/// Commands that speak to a running server.
std::vector<CommandSpec> server_commands();
/// Commands that start processes of their own (demo, soak, load).
std::vector<CommandSpec> fleet_starting_commands();
/// Commands that read and draw sites.
std::vector<CommandSpec> map_commands();
/// Commands that evaluate a part on core/ alone.
std::vector<CommandSpec> evaluation_commands();
/// Commands that read or write files alone (fleets, security, config keys, completion).
std::vector<CommandSpec> tool_commands();

}  // namespace fleet::cli::specs
