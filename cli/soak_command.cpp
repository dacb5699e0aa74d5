// `fleetctl soak`: the demo's fleet (real server and agents as processes, automatic orders) under
// ground-truth watch — collisions, deadlocks, lost and duplicated orders — with faults injected
// on a seeded schedule.

#include <algorithm>
#include <fstream>
#include <set>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "cli/fleet_run.hpp"
#include "cli/soak_parts.hpp"
#include "common/args.hpp"
#include "common/clock.hpp"
#include "common/paths.hpp"
#include "map/site.hpp"
#include "model/names.hpp"
#include "monitor/fault_plan.hpp"

namespace fleet::cli {

namespace {

constexpr double kFaultPeriodSim = 120.0;  // a fault every two simulated minutes

/// What the command line asks of a soak run, checked before any process starts.
struct SoakRequest {
  RunOptions options;
  config::FleetConfig config;
  std::string traffic;
  std::vector<monitor::FaultKind> kinds;
};

SoakRequest parse_soak(const CommandArgs& command, std::uint32_t domain) {
  const CommandFlags args("soak", "", command.args);
  SoakRequest r{{}, config::load_fleet_config(command.config_file), "", {}};
  RunOptions& options = r.options;
  options.kind = "soak";
  options.config_file = command.config_file;
  options.domain = domain;
  options.agents = static_cast<int>(args.integer("agents").value_or(4));
  options.site = args.value("site").value_or(r.config.settings.get_string("site"));
  options.duration_s = args.number("duration").value_or(180.0);
  options.time_scale = args.number("time-scale").value_or(10.0);
  options.seed = args.integer("seed").value_or(r.config.settings.get_int("seed"));
  options.http_port = static_cast<int>(args.integer("http-port").value_or(0));
  options.agent_wrap = args.value("agent-wrap").value_or("");
  options.vda5050_vehicles = static_cast<int>(args.integer("vda5050-vehicles").value_or(0));
  options.standby = args.flag("standby");
  options.whole_tracks = args.flag("keep-tracks");
  options.standby_wrap = args.value("standby-wrap").value_or("");
  if (!options.standby_wrap.empty() && !options.standby) throw ArgError("--standby-wrap: needs --standby");
  r.traffic = args.value("traffic").value_or(r.config.settings.get_bool("traffic.enabled") ? "on" : "off");
  r.kinds = monitor::parse_fault_list(args.value("faults").value_or("none"));
  if (!options.standby && std::find(r.kinds.begin(), r.kinds.end(), monitor::FaultKind::kKillHost) != r.kinds.end()) {
    throw ArgError("--faults: kill-host needs --standby (a second server to take over)");
  }
  std::vector<std::string> settings{"traffic.enabled=" + std::string(r.traffic == "on" ? "true" : "false")};
  for (const std::string& v : args.values("set")) settings.push_back(v);
  if (args.flag("verbose")) {
    // Debug logs of every process in the run directory: traffic requests, grants and waits.
    options.extra_server_args.push_back("--verbose");
    options.extra_agent_args.push_back("--verbose");
  }
  known_site_path(command.source_dir, options.site);
  // Checked here, named as given, before any process starts.
  for (const auto& s : settings) config::apply_set_flag(r.config, s);
  for (const auto& s : settings) {
    options.extra_server_args.insert(options.extra_server_args.end(), {"--set", s});
    options.extra_agent_args.insert(options.extra_agent_args.end(), {"--set", s});
  }
  FleetClient probe(domain);
  if (probe.find_server(std::chrono::milliseconds(1200))) {
    throw ArgError("a fleet-server already runs on DDS domain " + std::to_string(domain) +
                   "; stop it or choose another --domain");
  }
  return r;
}

/// The fault kinds the site allows; the others in `skipped` with the reason. map-switch needs
/// another map of the site to switch to (a revision: see map::site_revisions).
std::vector<monitor::FaultKind> faults_for_site(const SoakRequest& r, const std::vector<std::string>& site_maps,
                                                const std::vector<std::string>& obstacle_ids,
                                                std::map<std::string, std::string>& skipped) {
  std::vector<monitor::FaultKind> active;
  for (auto k : r.kinds) {
    if (k == monitor::FaultKind::kMapSwitch && site_maps.size() < 2) {
      skipped[to_string(k)] = "site " + r.options.site + " has no other map in maps/ to switch to";
    } else if (k == monitor::FaultKind::kObstacles && obstacle_ids.empty()) {
      skipped[to_string(k)] = "site " + r.options.site + " has no designated obstacles";
    } else {
      active.push_back(k);
    }
  }
  return active;
}

}  // namespace

int soak_command(const CommandArgs& command, std::ostream& out, std::ostream& err, std::uint32_t domain) {
  const SoakRequest request = parse_soak(command, domain);
  const RunOptions& options = request.options;
  const map::Site site = map::load_site(map::site_path(maps_dir(), options.site));
  std::vector<std::string> obstacle_ids;
  for (const auto& o : site.static_obstacles) obstacle_ids.push_back(o.id);
  const std::vector<std::string> site_maps = map::site_revisions(site);
  SoakObservations seen;
  seen.traffic = request.traffic;
  const auto active = faults_for_site(request, site_maps, obstacle_ids, seen.faults_skipped);
  auto plan =
      monitor::plan_faults(active, options.duration_s * options.time_scale, kFaultPeriodSim, 60.0, options.agents,
                           static_cast<int>(obstacle_ids.size()), static_cast<std::uint64_t>(options.seed));

  install_stop_handlers();
  auto log = make_logger("fleetctl soak");
  FleetRun run(options, request.config, log);
  run.start();
  err << "Fleet soak: fleet-server and " << options.agents << " fleet-agents (" << model::join(run.robot_ids())
      << ") on DDS domain " << domain << ", site " << options.site << ", time scale " << options.time_scale
      << ", traffic " << request.traffic << ", " << plan.size() << " faults planned"
      << (request.kinds.empty() ? "" : " (" + std::to_string(request.kinds.size()) + " kinds)") << ", "
      << options.duration_s << " s wall.\n  logs: " << run.run_dir() << "/\n";
  for (const auto& [kind, why] : seen.faults_skipped) err << "  fault " << kind << " skipped: " << why << "\n";

  // The soak's own DDS reader of the server's view, for when it marks robots lost.
  FleetClient client(domain);
  dds::Reader<model::FleetView> view_reader(client.participant(), dds::qos::live_state());
  dds::Reader<model::OrderReport> report_reader(client.participant(), dds::qos::latched_state(),
                                                dds::robot_report_partitions());
  std::map<std::string, bool> lost;
  SoakFaults faults(run, client, log, std::move(plan), obstacle_ids, site_maps, options.time_scale);
  seen.faults = &faults.records();
  SoakUsage usage(run, options.duration_s);
  const double start_wall = SimClock::wall_now();
  double next_progress = 10.0;
  while (run.poll()) {
    const double now_wall = SimClock::wall_now();
    const double elapsed = now_wall - start_wall;
    const double elapsed_sim = elapsed * options.time_scale;
    view_reader.take_data([&](model::FleetView&& view) {
      for (const auto& r : view.robots) {
        const bool is_lost = r.task_state == "LOST";
        if (is_lost && !lost[r.robot_id]) {
          seen.losses.push_back({r.robot_id, now_wall, elapsed_sim});
          faults.robot_lost(r.robot_id, now_wall);
        }
        lost[r.robot_id] = is_lost;
      }
    });
    report_reader.take_data([&](model::OrderReport&& report) {
      if (report.status != "DONE") return;
      seen.done_by[report.order_id].insert(report.robot_id);
      usage.order_done(report.robot_id);
    });
    faults.follow_recovery(lost, now_wall);
    faults.step(now_wall, elapsed_sim);
    usage.step(elapsed);
    if (run.wall_seconds() >= next_progress) {
      const auto t = run.tally();
      err << "  t=" << static_cast<int>(run.sim_seconds()) << " s sim: " << t.done << " orders done, " << t.open
          << " open, " << t.failed << " failed, " << run.collisions().size() << " collisions, "
          << run.progress().deadlocks().size() << " deadlocks, " << faults.records().size() << " faults\n";
      next_progress += 10.0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  faults.undo_all();
  usage.finish();
  if (const auto info = client.find_server(std::chrono::milliseconds(500)))
    seen.refused_samples = info->refused_samples;
  seen.wall = run.wall_seconds();
  run.stop();
  seen.usage = usage.figures(seen.wall, options.agents);

  const nlohmann::json summary = soak_summary(run, options, seen);
  // Kept with the logs and tracks, so a run read back later still has its figures.
  std::ofstream(run.run_dir() + "/summary.json") << summary.dump(2) << "\n";
  if (command.json) {
    out << summary.dump() << "\n";
  } else {
    print_soak_summary(out, run, summary);
  }
  return summary["failures"].empty() ? kExitOk : kExitFailed;
}

}  // namespace fleet::cli
