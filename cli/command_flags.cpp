#include "cli/command_flags.hpp"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "cli/commands.hpp"
#include "common/args.hpp"
#include "model/names.hpp"

namespace fleet::cli {

namespace {

using Kind = FlagSpec::Kind;
using Type = FlagSpec::Type;

std::string range_text(const FlagSpec& flag) {
  return format_number(flag.min) + " .. " + format_number(flag.max);
}

/// ArgError unless `text` is a value of `flag`'s type, range and choices.
void check_value(const FlagSpec& flag, const std::string& text) {
  const std::string where = "flag " + flag.name + ": ";
  if (flag.kind == Kind::kChoice && std::find(flag.choices.begin(), flag.choices.end(), text) == flag.choices.end()) {
    throw ArgError(where + "'" + text + "' is not one of " + model::join(flag.choices, ", "));
  }
  switch (flag.type) {
    case Type::kText:
      return;
    case Type::kUnsigned:
      if (!parse_u64(text)) throw ArgError(where + "'" + text + "' is not a non-negative integer");
      return;
    case Type::kInteger: {
      const auto v = parse_long(text);
      if (!v) throw ArgError(where + "'" + text + "' is not an integer");
      if (static_cast<double>(*v) < flag.min || static_cast<double>(*v) > flag.max) {
        throw ArgError(where + text + " is outside " + range_text(flag));
      }
      return;
    }
    case Type::kNumber: {
      const auto v = parse_finite(text);
      if (!v) throw ArgError(where + "'" + text + "' is not a number");
      if (*v < flag.min || *v > flag.max) throw ArgError(where + text + " is outside " + range_text(flag));
      return;
    }
  }
}

/// The flag `name` (with dashes) of `spec` or a global one (--json, --config, ...); nullptr when none.
const FlagSpec* find_flag(const CommandSpec& spec, std::string_view name) {
  for (const auto* flags : {&spec.flags, &global_flags()}) {
    for (const FlagSpec& f : *flags) {
      if (f.name == name) return &f;
    }
  }
  return nullptr;
}

/// "order add", "dock-eval".
std::string command_words(const CommandSpec& spec) {
  return spec.subcommand.empty() ? spec.command : spec.command + " " + spec.subcommand;
}

const CommandSpec& spec_or_throw(std::string_view command, std::string_view subcommand) {
  if (const CommandSpec* spec = find_command(command, subcommand)) return *spec;
  throw std::logic_error("the command table has no entry '" + std::string(command) + " " + std::string(subcommand) +
                         "'");
}

}  // namespace

const CommandSpec* find_command(std::string_view command, std::string_view subcommand) {
  const auto& table = command_table();
  for (const CommandSpec& spec : table) {
    if (spec.command == command && spec.subcommand == subcommand) return &spec;
  }
  return nullptr;
}

CommandFlags::CommandFlags(std::string_view command, std::string_view subcommand, const std::vector<std::string>& args)
    : CommandFlags(spec_or_throw(command, subcommand), args) {}

CommandFlags::CommandFlags(const CommandSpec& spec, const std::vector<std::string>& args) : spec_(spec) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& word = args[i];
    if (word == "-h" || word == "--help") {
      asks_for_usage_ = true;
      continue;
    }
    if (!looks_like_flag(word)) {
      positionals_.push_back(word);
      continue;
    }
    const std::size_t equals = word.find('=');
    const std::string name = word.substr(0, equals);
    const FlagSpec* flag = find_flag(spec, name);
    if (flag == nullptr) {
      std::vector<std::string> names;
      for (const FlagSpec& f : spec.flags) names.push_back(f.name);
      throw ArgError("unknown flag '" + name + "' for " + command_words(spec) +
                     (names.empty() ? " (it takes none)" : "; it takes " + model::join(names, ", ")));
    }
    if (flag->kind == Kind::kSwitch) {
      if (equals != std::string::npos) throw ArgError("flag " + name + " takes no value");
      given_[name].emplace_back();
      continue;
    }
    std::string text;
    if (equals != std::string::npos) {
      text = word.substr(equals + 1);
    } else {
      if (i + 1 >= args.size()) throw ArgError("flag " + name + " needs a value (" + flag->hint + ")");
      text = args[++i];
    }
    check_value(*flag, text);
    given_[name].push_back(std::move(text));
  }
  if (spec.positionals.empty() && !positionals_.empty()) {
    throw ArgError("unexpected argument '" + positionals_.front() + "'");
  }
}

const FlagSpec& CommandFlags::declared(std::string_view name, FlagSpec::Type type) const {
  const std::string dashed = (name.size() == 1 ? "-" : "--") + std::string(name);
  const FlagSpec* flag = find_flag(spec_, dashed);
  if (flag == nullptr || (type != Type::kText && flag->type != type)) {
    throw std::logic_error("fleetctl " + spec_.command + " reads " + dashed +
                           " as its command table does not declare it");
  }
  return *flag;
}

bool CommandFlags::flag(std::string_view name) const {
  const FlagSpec& f = declared(name, Type::kText);
  if (f.kind != Kind::kSwitch) throw std::logic_error(f.name + " is no switch");
  return given_.contains(f.name);
}

std::optional<std::string> CommandFlags::value(std::string_view name) const {
  const FlagSpec& f = declared(name, Type::kText);
  const auto it = given_.find(f.name);
  if (it == given_.end()) return std::nullopt;
  return it->second.back();
}

std::vector<std::string> CommandFlags::values(std::string_view name) const {
  const FlagSpec& f = declared(name, Type::kText);
  const auto it = given_.find(f.name);
  return it == given_.end() ? std::vector<std::string>{} : it->second;
}

std::optional<long> CommandFlags::integer(std::string_view name) const {
  const FlagSpec& f = declared(name, Type::kInteger);
  const auto it = given_.find(f.name);
  if (it == given_.end()) return std::nullopt;
  return parse_long(it->second.back());
}

std::optional<double> CommandFlags::number(std::string_view name) const {
  const FlagSpec& f = declared(name, Type::kNumber);
  const auto it = given_.find(f.name);
  if (it == given_.end()) return std::nullopt;
  return parse_finite(it->second.back());
}

std::optional<std::uint64_t> CommandFlags::u64(std::string_view name) const {
  const FlagSpec& f = declared(name, Type::kUnsigned);
  const auto it = given_.find(f.name);
  if (it == given_.end()) return std::nullopt;
  return parse_u64(it->second.back());
}

std::string CommandFlags::usage() const {
  std::string text = "usage: fleetctl " + usage_line(spec_) + "\n";
  std::istringstream summary(spec_.summary);
  for (std::string line; std::getline(summary, line);) text += "  " + line + "\n";
  return text;
}

}  // namespace fleet::cli

namespace fleet::cli {

std::optional<CommandFlags> flags_or_report(std::string_view command, std::string_view subcommand,
                                            const std::vector<std::string>& args, std::ostream& err) {
  const CommandSpec& spec = spec_or_throw(command, subcommand);
  try {
    return CommandFlags(spec, args);
  } catch (const ArgError& e) {
    err << command_words(spec) << ": " << e.what() << "\nusage: fleetctl " << usage_line(spec) << "\n";
    return std::nullopt;
  }
}

std::optional<CommandFlags> flags_or_exit(std::string_view command, const std::vector<std::string>& args,
                                          std::ostream& out, std::ostream& err, int& exit_code) {
  auto flags = flags_or_report(command, args, err);
  if (!flags) {
    exit_code = kExitBadInput;
    return std::nullopt;
  }
  if (flags->asks_for_usage()) {
    out << flags->usage();
    exit_code = kExitOk;
    return std::nullopt;
  }
  return flags;
}

}  // namespace fleet::cli
