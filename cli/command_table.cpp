#include "cli/command_table.hpp"

#include <algorithm>
#include <set>
#include <sstream>

#include "cli/command_specs.hpp"
#include "cli/commands.hpp"
#include "cli/fleet_run.hpp"
#include "model/names.hpp"
#include "orders/order_request_check.hpp"

namespace fleet::cli {

namespace {

using namespace specs;

std::vector<CommandSpec> make_table() {
  std::vector<CommandSpec> table = server_commands();
  for (auto* part : {fleet_starting_commands, map_commands, evaluation_commands, tool_commands}) {
    for (CommandSpec& spec : part()) table.push_back(std::move(spec));
  }
  return table;
}

std::vector<FlagSpec> make_global_flags() {
  return {value("--domain", "N"),   on_off("--json"),          value("--timeout", "S"),
          file("--config", "FILE"), file("--security", "DIR"), on_off("--help")};
}

std::string flag_usage(const FlagSpec& flag) {
  // Appended piece by piece: GCC 12 warns wrongly (-Wrestrict) about "literal" + std::string.
  std::string text = flag.required ? "" : "[";
  text += flag.name;
  if (flag.kind != Kind::kSwitch) {
    text += ' ';
    text += flag.kind == Kind::kChoice && flag.hint.empty() ? model::join(flag.choices, "|") : flag.hint;
  }
  if (!flag.required) text += ']';
  return text;
}

/// "a b c" quoted, for a bash word list.
std::string words(const std::vector<std::string>& items) {
  std::string quoted(1, '"');
  quoted += model::join(items, " ");
  quoted += '"';
  return quoted;
}

const char* group_title(Group group) {
  switch (group) {
    case Group::kServer:
      return "commands (need a running fleet-server):";
    case Group::kStartsFleet:
      return "commands that start a fleet:";
    case Group::kOffline:
      return "offline tools (core libraries only, no DDS):";
  }
  return "";
}

std::string kind_name(Kind kind) {
  switch (kind) {
    case Kind::kSwitch:
      return "switch";
    case Kind::kValue:
      return "value";
    case Kind::kFile:
      return "file";
    case Kind::kChoice:
      return "choice";
  }
  return "";
}

nlohmann::json flag_json(const FlagSpec& flag) {
  return {{"name", flag.name},
          {"kind", kind_name(flag.kind)},
          {"hint", flag.hint},
          {"choices", flag.choices},
          {"required", flag.required}};
}

}  // namespace

const std::vector<CommandSpec>& command_table() {
  static const std::vector<CommandSpec> table = make_table();
  return table;
}

const std::vector<FlagSpec>& global_flags() {
  static const std::vector<FlagSpec> flags = make_global_flags();
  return flags;
}

std::vector<std::string> command_names() {
  std::vector<std::string> names;
  for (const auto& spec : command_table()) {
    if (std::find(names.begin(), names.end(), spec.command) == names.end()) names.push_back(spec.command);
  }
  return names;
}

std::string usage_line(const CommandSpec& spec) {
  std::string line = spec.command;
  for (const std::string& word : {spec.subcommand, spec.positionals}) {
    if (!word.empty()) line += ' ' + word;
  }
  for (const auto& flag : spec.flags) line += ' ' + flag_usage(flag);
  return line;
}

std::string help_text() {
  constexpr std::size_t kSummaryColumn = 23;
  std::ostringstream out;
  out << "usage: fleetctl [global flags] COMMAND [flags]\n\n"
         "Drive a Fleet from the terminal or from scripts. fleetctl is a DDS participant of its own.\n"
         "Every command takes --json.\n";
  for (const Group group : {Group::kServer, Group::kStartsFleet, Group::kOffline}) {
    out << "\n" << group_title(group) << "\n";
    for (const auto& spec : command_table()) {
      if (spec.group != group) continue;
      const std::string usage = "  " + usage_line(spec);
      std::istringstream summary(spec.summary);
      std::string first;
      std::getline(summary, first);
      if (usage.size() + 1 < kSummaryColumn) {
        out << usage << std::string(kSummaryColumn - usage.size(), ' ') << first << "\n";
      } else {
        out << usage << "\n" << std::string(kSummaryColumn, ' ') << first << "\n";
      }
      for (std::string more; std::getline(summary, more);) out << std::string(kSummaryColumn, ' ') << more << "\n";
    }
  }
  out << R"(
global flags:
  --domain N           DDS domain id (default: dds.domain of the configuration)
  --json               machine-readable output: one JSON document (the last line printed);
                       streams (order watch, inject) print JSON lines, the last one a summary
  --timeout S          seconds to look for the server (default 3); order watch, inject --wait
                       and order add --wait also stop following orders after S seconds
  --config FILE        configuration (default: config/fleet.yaml)
  --security DIR       join the DDS domain with DDS Security as 'operator', with the credentials
                       of DIR (fleetctl security init; default: dds.security); demo and soak
                       start every process with its own credentials from DIR
  --help               this text

exit codes:
  0  ok
  1  the operation ran and failed (order FAILED or CANCELLED, an order not placed or lost,
     a run lost orders)
  2  bad input (unknown area, robot, obstacle, map or key; malformed file; bad flag)
  3  no fleet-server reachable on the DDS domain (or it went away)
)";
  return out.str();
}

std::string bash_completion_script() {
  // Flags that take a value make the next word a value, not a command; the walk over the words
  // typed so far must skip those to find the command and subcommand.
  std::set<std::string> valued;
  std::vector<std::string> global;
  for (const auto& flag : global_flags()) {
    global.push_back(flag.name);
    if (flag.kind != Kind::kSwitch) valued.insert(flag.name);
  }
  std::vector<std::pair<std::string, const FlagSpec*>> value_completions;
  const auto note_flag = [&](const FlagSpec& flag) {
    if (flag.kind == Kind::kSwitch) return;
    valued.insert(flag.name);
    if (flag.kind == Kind::kFile || flag.kind == Kind::kChoice) {
      const bool seen = std::any_of(value_completions.begin(), value_completions.end(),
                                    [&](const auto& entry) { return entry.first == flag.name; });
      if (!seen) value_completions.emplace_back(flag.name, &flag);
    }
  };
  for (const auto& flag : global_flags()) note_flag(flag);
  for (const auto& spec : command_table()) {
    for (const auto& flag : spec.flags) note_flag(flag);
  }

  std::ostringstream s;
  s << "# bash completion for fleetctl, generated by `fleetctl completion bash` from its command table.\n"
       "# Load it with:  source <(fleetctl completion bash)\n"
       "_fleetctl() {\n"
       "  local cur=\"${COMP_WORDS[COMP_CWORD]}\" prev=\"\"\n"
       "  (( COMP_CWORD > 0 )) && prev=\"${COMP_WORDS[COMP_CWORD-1]}\"\n"
       "  local valued=\" "
    << model::join(std::vector<std::string>(valued.begin(), valued.end()), " ")
    << " \"\n"
       "  local global="
    << words(global)
    << "\n"
       "  local command=\"\" sub=\"\" skip=0 i word\n"
       "  for (( i = 1; i < COMP_CWORD; i++ )); do\n"
       "    word=\"${COMP_WORDS[i]}\"\n"
       "    if (( skip )); then skip=0; continue; fi\n"
       "    case \"$word\" in\n"
       "      -*=*) ;;\n"
       "      -*) [[ \"$valued\" == *\" $word \"* ]] && skip=1 ;;\n"
       "      *) if [[ -z \"$command\" ]]; then command=\"$word\"; elif [[ -z \"$sub\" ]]; then sub=\"$word\"; fi ;;\n"
       "    esac\n"
       "  done\n"
       "  case \"$prev\" in\n";
  for (const auto& [name, flag] : value_completions) {
    s << "    " << name << ") ";
    if (flag->kind == Kind::kFile) {
      s << "compopt -o filenames 2>/dev/null; mapfile -t COMPREPLY < <(compgen -f -- \"$cur\"); return ;;\n";
    } else {
      s << "mapfile -t COMPREPLY < <(compgen -W " << words(flag->choices) << " -- \"$cur\"); return ;;\n";
    }
  }
  s << "  esac\n"
       "  if [[ \"$valued\" == *\" $prev \"* ]]; then COMPREPLY=(); return; fi\n"
       "  local candidates=\"\" files=0\n"
       "  case \"$command\" in\n"
       "    \"\") candidates="
    << words(command_names()) << " ;;\n";
  for (const auto& name : command_names()) {
    std::vector<const CommandSpec*> entries;
    for (const auto& spec : command_table()) {
      if (spec.command == name) entries.push_back(&spec);
    }
    const auto flags_of = [](const CommandSpec& spec) {
      std::vector<std::string> names;
      for (const auto& flag : spec.flags) names.push_back(flag.name);
      return words(names);
    };
    s << "    " << name << ")\n";
    if (entries.size() == 1 && entries[0]->subcommand.empty()) {
      s << "      candidates=" << flags_of(*entries[0]) << (entries[0]->positional_files ? "; files=1" : "") << " ;;\n";
      continue;
    }
    std::vector<std::string> subcommands;
    for (const auto* entry : entries) subcommands.push_back(entry->subcommand);
    s << "      case \"$sub\" in\n"
         "        \"\") candidates="
      << words(subcommands) << " ;;\n";
    for (const auto* entry : entries) {
      s << "        " << entry->subcommand << ") candidates=" << flags_of(*entry)
        << (entry->positional_files ? "; files=1" : "") << " ;;\n";
    }
    s << "      esac ;;\n";
  }
  s << "  esac\n"
       "  if [[ \"$cur\" == -* ]]; then candidates=\"$candidates $global\"; fi\n"
       "  mapfile -t COMPREPLY < <(compgen -W \"$candidates\" -- \"$cur\")\n"
       "  if (( files )) && [[ \"$cur\" != -* ]]; then\n"
       "    compopt -o filenames 2>/dev/null\n"
       "    mapfile -t -O \"${#COMPREPLY[@]}\" COMPREPLY < <(compgen -f -- \"$cur\")\n"
       "  fi\n"
       "}\n"
       "complete -F _fleetctl fleetctl\n";
  return s.str();
}

nlohmann::json command_table_json() {
  nlohmann::json commands = nlohmann::json::array();
  for (const auto& spec : command_table()) {
    nlohmann::json flags = nlohmann::json::array();
    for (const auto& flag : spec.flags) flags.push_back(flag_json(flag));
    commands.push_back({{"command", spec.command},
                        {"subcommand", spec.subcommand},
                        {"positionals", spec.positionals},
                        {"flags", flags},
                        {"usage", usage_line(spec)},
                        {"summary", spec.summary}});
  }
  nlohmann::json global = nlohmann::json::array();
  for (const auto& flag : global_flags()) global.push_back(flag_json(flag));
  return {{"commands", commands}, {"global_flags", global}};
}

}  // namespace fleet::cli
