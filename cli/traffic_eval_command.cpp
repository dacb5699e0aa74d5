// fleetctl traffic-eval: the traffic manager on a site with the configuration's fleets, robots
// driven kinematically by the core simulator (a load generator, not the agents), and the same run
// on a revision of the site for comparison.

#include <algorithm>
#include <iomanip>
#include <nlohmann/json.hpp>

#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "common/args.hpp"
#include "common/paths.hpp"
#include "config/fleet_config.hpp"
#include "coordination/place_sim.hpp"
#include "map/site_map.hpp"
#include "model/names.hpp"
#include "traffic/one_way.hpp"
#include "traffic/traffic_settings.hpp"
#include "traffic/traffic_sim.hpp"

namespace fleet::cli {

namespace {

struct EvalSpec {
  int robots = 8;
  double duration_s = 1800.0;
  double dwell_s = 10.0;
  std::uint64_t seed = 1;
  std::vector<std::string> place_prefixes;    ///< trips only between places whose ids start so; empty: all
  bool verbose = false;                       ///< list every deadlock: who stalled where, waiting on whom
  std::vector<std::string> cores{"manager"};  ///< "manager" (TrafficManager), "pibt" (PlacePibt), or both
  bool one_way = false;            ///< --lanes one-way: the planner on the one-way corridors the manager drives
  double delay_probability = 0.0;  ///< --delay P,MIN,MAX: per move, seconds
  double delay_min_s = 0.0;
  double delay_max_s = 0.0;
};

/// The same trips coordinated by the place planner (coordination::PlaceSim) instead of the manager.
nlohmann::json run_place_planner(const std::string& site_name, const map::SiteMap& site,
                                 const traffic::ConflictZones& zones, const traffic::SimParams& params,
                                 const traffic::SimScenario& scenario, const EvalSpec& spec) {
  coordination::PlaceSimParams place_params;
  place_params.speed = params.speed;
  place_params.dwell = params.dwell;
  place_params.deadlock_timeout = params.deadlock_timeout;
  place_params.robot_types = params.robot_types;
  place_params.seed = params.seed;
  place_params.delay_probability = spec.delay_probability;
  place_params.delay_min_s = spec.delay_min_s;
  place_params.delay_max_s = spec.delay_max_s;
  // --lanes one-way: the corridors on cycles driven one way, as the traffic manager drives them.
  const map::RoadGraph lanes = spec.one_way ? traffic::one_way_plan(site.graph.graph, zones).graph : site.graph.graph;
  coordination::PlaceSim sim(lanes, zones, place_params, scenario.goal_points, scenario.start_points);
  const coordination::PlaceSimReport& r = sim.run_until(spec.duration_s);
  return {{"site", site_name},
          {"core", "pibt"},
          {"lanes", spec.one_way ? "one-way" : "both"},
          {"trips", r.trips},
          {"mean_trip_s", r.mean_trip_s},
          {"collisions", r.collisions},
          {"deadlocks", r.deadlocks},
          {"max_wait_s", r.max_wait_s},
          {"plan_conflicts", r.plan_conflicts},
          {"wait_cycles", r.wait_cycles},
          {"first_wait_cycle", r.first_wait_cycle},
          {"delays", r.delays},
          {"planning_ms_mean", r.planning_ms_mean},
          {"planning_ms_max", r.planning_ms_max},
          {"first_collision", r.first_collision},
          {"first_plan_conflict", r.first_plan_conflict},
          {"reroutes", 0},
          {"stalls", spec.verbose ? nlohmann::json(r.stall_notes) : nlohmann::json::array()}};
}

nlohmann::json run_site(const std::string& site_name, const std::string& core, const config::FleetConfig& config,
                        const EvalSpec& spec) {
  map::SiteMap site = map::load_site_map(map::site_path(maps_dir(), site_name));
  if (!spec.place_prefixes.empty()) {
    std::erase_if(site.site.loading_areas, [&](const map::LoadingArea& area) {
      return std::none_of(spec.place_prefixes.begin(), spec.place_prefixes.end(),
                          [&](const std::string& prefix) { return area.id.starts_with(prefix); });
    });
    if (site.site.loading_areas.size() < 2) {
      throw ArgError("--places: fewer than two places of " + site_name + " start with " +
                     model::join(spec.place_prefixes));
    }
  }
  traffic::TrafficConfiguration configuration = traffic::configuration_from(config);
  const traffic::ConflictZones zones(site.graph.graph, configuration.resources);
  traffic::SimParams params;
  params.seed = spec.seed;
  params.dwell = spec.dwell_s;
  params.check_invariant = false;
  // Robots take their fleets in turn, as `fleetctl demo` starts them; all drive at the slowest
  // fleet's top speed so that the sites, not the vehicles, make the difference.
  params.speed = 1e9;
  for (std::size_t f = 0; f < config.fleets.size(); ++f) {
    params.speed = std::min(params.speed, config.fleets[f].profile.max_speed);
  }
  for (int i = 0; i < spec.robots; ++i) params.robot_types.push_back(i % static_cast<int>(config.fleets.size()));
  params.footprint = config.fleets.front().footprint;
  const auto scenario =
      traffic::site_scenario(site, zones, spec.robots, site.site.approach_distance, params.robot_types);
  if (core == "pibt") return run_place_planner(site_name, site, zones, params, scenario, spec);
  traffic::TrafficSim sim(site.graph.graph, configuration, params, scenario.goal_points, scenario.start_points);
  const traffic::SimReport& r = sim.run_until(spec.duration_s);
  return {{"site", site_name},
          {"core", "manager"},
          {"trips", r.trips},
          {"mean_trip_s", r.mean_trip_s},
          {"collisions", r.collisions},
          {"deadlocks", r.deadlocks},
          {"max_wait_s", r.max_wait_s},
          {"reroutes", r.reroutes},
          {"sidings", r.sidings},
          {"first_collision", r.first_collision},
          {"stalls", spec.verbose ? nlohmann::json(r.stall_notes) : nlohmann::json::array()}};
}

}  // namespace

int traffic_eval_command(const CommandArgs& args, std::ostream& out, std::ostream& /*err*/) {
  const CommandFlags flags("traffic-eval", "", args.args);
  const config::FleetConfig config = config::load_fleet_config(args.config_file);
  const std::string site = flags.value("site").value_or(config.settings.get_string("site"));
  const auto against = flags.value("against");
  EvalSpec spec;
  spec.robots = static_cast<int>(flags.integer("robots").value_or(spec.robots));
  spec.duration_s = flags.number("duration").value_or(spec.duration_s);
  spec.dwell_s = flags.number("dwell").value_or(spec.dwell_s);
  spec.seed = flags.u64("seed").value_or(spec.seed);
  spec.verbose = flags.flag("verbose");
  if (const auto places = flags.value("places")) {
    std::string rest = *places;
    for (std::size_t comma; (comma = rest.find(',')) != std::string::npos; rest.erase(0, comma + 1)) {
      if (comma > 0) spec.place_prefixes.push_back(rest.substr(0, comma));
    }
    if (!rest.empty()) spec.place_prefixes.push_back(rest);
  }
  if (const auto core = flags.value("core")) {
    // The command table's choices: manager, pibt, both.
    spec.cores = *core == "both" ? std::vector<std::string>{"manager", "pibt"} : std::vector<std::string>{*core};
  }
  if (const auto lanes = flags.value("lanes")) {
    if (*lanes == "one-way" && spec.cores == std::vector<std::string>{"manager"}) {
      throw ArgError("--lanes one-way: the traffic manager drives its own one-way plan; give --core pibt or both");
    }
    spec.one_way = *lanes == "one-way";
  }
  if (const auto delay = flags.value("delay")) {
    std::vector<std::string> parts{""};
    for (const char c : *delay) {
      if (c == ',') {
        parts.emplace_back();
      } else {
        parts.back().push_back(c);
      }
    }
    // -1 stands for a part that is missing or no number: every check below refuses it.
    const auto part = [&](std::size_t i) { return parts.size() == 3 ? parse_finite(parts[i]).value_or(-1.0) : -1.0; };
    const double p = part(0), lo = part(1), hi = part(2);
    if (p < 0.0 || p > 1.0 || lo < 0.0 || hi < lo || hi > 3600.0) {
      throw ArgError("--delay '" + *delay + "': expected P,MIN,MAX with 0 <= P <= 1 and 0 <= MIN <= MAX (seconds)");
    }
    if (spec.cores != std::vector<std::string>{"pibt"}) {
      throw ArgError("--delay: only the coordination core's runs model delays (--core pibt)");
    }
    spec.delay_probability = p;
    spec.delay_min_s = lo;
    spec.delay_max_s = hi;
  }
  if (against && spec.cores.size() > 1) throw ArgError("--core both compares cores on one site: drop --against");
  for (const auto& name : against ? std::vector<std::string>{site, *against} : std::vector<std::string>{site}) {
    if (!std::filesystem::exists(map::site_path(maps_dir(), name))) {
      throw ArgError(model::unknown_name_message("site", name, map::site_names(maps_dir())));
    }
  }
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& core : spec.cores) runs.push_back(run_site(site, core, config, spec));
  if (against) runs.push_back(run_site(*against, spec.cores.front(), config, spec));
  nlohmann::json doc{{"config", config.source},
                     {"robots", spec.robots},
                     {"duration_s", spec.duration_s},
                     {"seed", spec.seed},
                     {"dwell_s", spec.dwell_s},
                     {"places", spec.place_prefixes},
                     {"delay", {spec.delay_probability, spec.delay_min_s, spec.delay_max_s}},
                     {"runs", runs}};
  if (against) {
    const double b = runs[1]["trips"].get<double>();
    doc["trips_ratio"] = b > 0.0 ? runs[0]["trips"].get<double>() / b : 0.0;
  } else if (runs.size() == 2) {
    const double manager = runs[0]["trips"].get<double>();
    doc["pibt_over_manager"] = manager > 0.0 ? runs[1]["trips"].get<double>() / manager : 0.0;
  }
  if (args.json) {
    out << doc.dump() << "\n";
    return kExitOk;
  }
  out << "traffic-eval: " << spec.robots << " robots of " << config.source << ", " << spec.duration_s << " s sim, seed "
      << spec.seed << " (kinematic robots, a load generator, under the real coordination)\n";
  for (const auto& r : runs) {
    out << "  " << std::left << std::setw(18) << r["site"].get<std::string>() << std::setw(9)
        << r["core"].get<std::string>() << r["trips"].get<long>() << " trips, " << r["collisions"].get<long>()
        << " collisions, " << r["deadlocks"].get<long>() << " deadlocks, longest wait " << std::fixed
        << std::setprecision(1) << r["max_wait_s"].get<double>() << " s, " << r["reroutes"].get<long>()
        << " re-routes\n";
    for (const auto& note : r["stalls"]) out << "    " << note.get<std::string>() << "\n";
  }
  if (against) {
    out << "  trips ratio " << site << " / " << *against << ": " << std::setprecision(2)
        << doc["trips_ratio"].get<double>() << "\n";
  } else if (runs.size() == 2) {
    out << "  trips ratio pibt / manager: " << std::setprecision(2) << doc["pibt_over_manager"].get<double>() << "\n";
  }
  return kExitOk;
}

}  // namespace fleet::cli
