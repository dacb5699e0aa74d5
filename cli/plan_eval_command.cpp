// fleetctl plan-eval: argument parsing and printing only; the evaluation is planning::run_plan_eval.
#include <exception>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "cli/commands.hpp"
#include "common/args.hpp"
#include "common/errors.hpp"
#include "map/site.hpp"
#include "map/site_map.hpp"
#include "planning/plan_eval.hpp"

namespace fleet::cli {

namespace {

constexpr const char* kUsage =
    "usage: fleetctl plan-eval --site NAME [--queries N] [--seed S] [--resolution M]\n"
    "                          [--optimal-budget-ms MS] [--no-ompl] [--json]\n"
    "Runs road_astar, grid_astar, grassfire, ompl_rrtconnect and ompl_bitstar on the same random\n"
    "start/goal pairs of maps/NAME.yaml and prints per planner the median and p95 time, the success\n"
    "rate and the mean path length relative to the shortest path any planner found for each query.\n";

}  // namespace

int plan_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& err) {
  planning::PlanEvalConfiguration config;
  std::string site_name;
  bool json = args.json;
  const auto& a = args.args;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string& flag = a[i];
    if (flag == "--json") {
      json = true;
      continue;
    }
    if (flag == "--no-ompl") {
      config.include_ompl = false;
      continue;
    }
    if (flag == "--help" || flag == "-h") {
      out << kUsage;
      return kExitOk;
    }
    const bool takes_value = flag == "--site" || flag == "--queries" || flag == "--seed" || flag == "--resolution" ||
                             flag == "--optimal-budget-ms";
    if (!takes_value) {
      err << "plan-eval: unknown flag '" << flag << "'\n" << kUsage;
      return kExitBadInput;
    }
    if (i + 1 >= a.size()) {
      err << "plan-eval: " << flag << " needs a value\n";
      return kExitBadInput;
    }
    const std::string& value = a[++i];
    const auto bad = [&](const char* what) {
      err << "plan-eval: " << flag << " '" << value << "' " << what << "\n";
      return kExitBadInput;
    };
    if (flag == "--site") {
      site_name = value;
    } else if (flag == "--queries") {
      const auto queries = parse_u64(value);
      if (!queries || *queries == 0 || *queries > 1000000) return bad("is not a count in [1, 1000000]");
      config.queries = static_cast<int>(*queries);
    } else if (flag == "--seed") {
      const auto seed = parse_u64(value);
      if (!seed) return bad("is not a non-negative integer");
      config.seed = *seed;
    } else if (flag == "--resolution") {
      const auto resolution = parse_finite(value);
      if (!resolution || *resolution < 0.005 || *resolution > 1.0) return bad("is not a cell size in [0.005, 1] m");
      config.resolution = *resolution;
    } else {
      const auto budget = parse_finite(value);
      if (!budget || *budget <= 0.0 || *budget > 60000.0) return bad("is not in (0, 60000]");
      config.optimal_budget_ms = *budget;
    }
  }
  if (site_name.empty()) {
    err << "plan-eval: --site is required\n" << kUsage;
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
