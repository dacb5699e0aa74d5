// fleetctl plan-eval: argument parsing and printing only; the evaluation is planning::run_plan_eval.
#include <exception>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "common/errors.hpp"
#include "map/site.hpp"
#include "map/site_map.hpp"
#include "planning/plan_eval.hpp"

namespace fleet::cli {

namespace {}  // namespace

int plan_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
  planning::PlanEvalConfiguration config;
  std::string site_name;
  bool json = args.json;
  int exit_code = kExitOk;
  const auto parsed = flags_or_exit("plan-eval", args.args, out, err, exit_code);
  if (!parsed) return exit_code;
  const CommandFlags& a = *parsed;
  try {
    if (a.flag("no-ompl")) config.include_ompl = false;
    if (const auto v = a.value("site")) site_name = *v;
    if (const auto v = a.integer("queries")) config.queries = static_cast<int>(*v);
    if (const auto v = a.u64("seed")) config.seed = *v;
    if (const auto v = a.number("resolution")) config.resolution = *v;
    if (const auto v = a.number("optimal-budget-ms")) config.optimal_budget_ms = *v;
    if (site_name.empty()) throw ArgError("--site is required");
  } catch (const ArgError& e) {
    err << "plan-eval: " << e.what() << '\n' << a.usage();
    return kExitBadInput;
  }

  planning::PlanEvalReport report;
  try {
    const std::string path = known_site_path(args.source_dir, site_name);
    const map::SiteMap site = map::load_site_map_unchecked(path);
    report = planning::run_plan_eval(site.site, site.graph.graph, config);
  } catch (const map::MapError& e) {
    err << "plan-eval: " << e.what() << '\n';
    return kExitBadInput;
  } catch (const InputError& e) {
    err << "plan-eval: " << e.what() << '\n';
    return kExitBadInput;
  } catch (const std::invalid_argument& e) {
    err << "plan-eval: " << e.what() << '\n';
    return kExitBadInput;
  }

  out << "plan-eval " << report.site << ": " << report.queries << " queries, seed " << report.seed << ", graph "
      << report.graph_points << " points (" << report.query_points << " in the main component), grid "
      << report.grid_width << " x " << report.grid_height << " at " << report.resolution * 100.0 << " cm\n";
  out << "  " << std::left << std::setw(18) << "planner" << std::right << std::setw(11) << "median ms" << std::setw(10)
      << "p95 ms" << std::setw(10) << "max ms" << std::setw(9) << "success" << std::setw(13) << "length ratio"
      << std::setw(11) << "max ratio" << '\n';
  for (const auto& p : report.planners) {
    out << "  " << std::left << std::setw(18) << p.name << std::right << std::fixed << std::setprecision(3)
        << std::setw(11) << p.median_ms << std::setw(10) << p.p95_ms << std::setw(10) << p.max_ms
        << std::setprecision(3) << std::setw(9) << p.success << std::setw(13) << p.length_ratio << std::setw(11)
        << p.max_length_ratio << '\n';
  }
  if (json) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& p : report.planners) {
      j[p.name] = {
          {"median_ms", p.median_ms}, {"p95_ms", p.p95_ms}, {"success", p.success}, {"length_ratio", p.length_ratio}};
    }
    out << j.dump() << '\n';
  }
  return kExitOk;
}

}  // namespace fleet::cli
