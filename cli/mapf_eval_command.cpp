// fleetctl mapf-eval: the coordination core on a League of Robot Runners 2023 instance, in the
// competition's discrete model, writing the competition's output file.

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "coordination/lifelong_run.hpp"

namespace fleet::cli {

namespace {

coordination::DelayModel parse_delay(const std::string& text) {
  // P,MIN,MAX
  std::vector<std::string> parts;
  std::string rest = text;
  for (std::size_t comma; (comma = rest.find(',')) != std::string::npos; rest.erase(0, comma + 1)) {
    parts.push_back(rest.substr(0, comma));
  }
  parts.push_back(rest);
  const auto p = parts.size() == 3 ? parse_finite(parts[0]) : std::nullopt;
  const auto lo = parts.size() == 3 ? parse_long(parts[1]) : std::nullopt;
  const auto hi = parts.size() == 3 ? parse_long(parts[2]) : std::nullopt;
  if (!p || !lo || !hi || *p < 0.0 || *p > 1.0 || *lo < 1 || *hi < *lo || *hi > 100000) {
    throw ArgError("--delay '" + text + "': expected P,MIN,MAX with 0 <= P <= 1 and 1 <= MIN <= MAX (steps)");
  }
  return {*p, static_cast<int>(*lo), static_cast<int>(*hi)};
}

}  // namespace

int mapf_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& /*err*/) {
  const CommandFlags flags("mapf-eval", "", args.args);
  const auto instance_path = flags.value("instance");
  coordination::LifelongSettings settings;
  settings.steps = static_cast<int>(flags.integer("steps").value_or(settings.steps));
  settings.window = static_cast<int>(flags.integer("window").value_or(settings.window));
  if (flags.value("planner") == "cells") settings.planner = coordination::GridPlanner::kCells;
  settings.guidance = flags.value("guidance").value_or("on") == "on";
  settings.lns_window = static_cast<int>(flags.integer("lns-window").value_or(settings.lns_window));
  settings.lns_rounds = static_cast<int>(flags.integer("lns-rounds").value_or(settings.lns_rounds));
  settings.lns_size = static_cast<int>(flags.integer("lns-size").value_or(settings.lns_size));
  if (settings.window == 0) settings.window = coordination::default_window(settings.planner);
  settings.seed = flags.u64("seed").value_or(settings.seed);
  if (const auto delay = flags.value("delay")) settings.delays = parse_delay(*delay);
  const auto output = flags.value("output");
  if (!instance_path) throw ArgError("mapf-eval needs --instance FILE.json (a League of Robot Runners 2023 instance)");

  const coordination::LorrInstance instance = coordination::load_lorr_instance(*instance_path);
  coordination::LifelongGridRun run(instance, settings);
  const coordination::LifelongResult& result = run.run();
  const coordination::LifelongFigures figures = coordination::figures_of(result);
  if (output) {
    std::ofstream file(*output, std::ios::trunc);
    if (!file) throw ArgError("--output " + *output + ": cannot write the file");
    file << coordination::lorr_output_json(instance, result) << "\n";
  }
  const nlohmann::json doc{
      {"instance", *instance_path},
      {"robots", instance.starts.size()},
      {"steps", result.steps},
      {"window", settings.window},
      {"planner", settings.planner == coordination::GridPlanner::kCells ? "cells" : "operations"},
      {"seed", settings.seed},
      {"guidance", settings.guidance && settings.planner == coordination::GridPlanner::kOperations},
      {"lns_window", settings.planner == coordination::GridPlanner::kOperations ? settings.lns_window : 0},
      {"delay", {settings.delays.probability, settings.delays.min_steps, settings.delays.max_steps}},
      {"finished", result.finished},
      {"throughput", figures.throughput},
      {"planning_ms_p50", figures.planning_ms_p50},
      {"planning_ms_p99", figures.planning_ms_p99},
      {"planning_ms_max", figures.planning_ms_max},
      {"longest_standstill", result.longest_standstill},
      {"delayed_robot_steps", result.delayed_robot_steps},
      {"wait_cycles", result.wait_cycles},
      {"errors", result.errors.size()},
      {"valid", result.errors.empty()},
      {"output", output.value_or("")}};
  out << "mapf-eval: " << instance.starts.size() << " robots on " << instance.map.source << ", " << result.steps
      << " steps, seed " << settings.seed << "\n"
      << "  errands finished   " << result.finished << " (" << std::fixed << std::setprecision(2) << figures.throughput
      << " a step)\n"
      << "  planning per step  median " << std::setprecision(3) << figures.planning_ms_p50 << " ms, p99 "
      << figures.planning_ms_p99 << " ms, max " << figures.planning_ms_max << " ms\n"
      << "  longest standstill " << result.longest_standstill << " steps with an errand\n"
      << "  valid              " << (result.errors.empty() ? "yes" : "NO: " + result.errors.front()) << ", "
      << result.wait_cycles << " wait cycles\n";
  if (settings.delays.probability > 0.0)
    out << "  delayed            " << result.delayed_robot_steps << " robot steps\n";
  if (output) out << "  output             " << *output << "\n";
  if (args.json) out << doc.dump() << "\n";
  return result.errors.empty() && result.wait_cycles == 0 ? kExitOk : kExitFailed;
}

}  // namespace fleet::cli
