// `fleetctl soak`: the demo's fleet (real server and agents as processes, automatic orders) under
// ground-truth watch — collisions, deadlocks, lost and duplicated orders — with faults injected
// on a seeded schedule.

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "cli/commands.hpp"
#include "cli/fleet_run.hpp"
#include "common/args.hpp"
#include "common/clock.hpp"
#include "common/paths.hpp"
#include "common/percentile.hpp"
#include "map/site.hpp"
#include "model/names.hpp"
#include "monitor/fault_plan.hpp"
#include "monitor/order_accounting.hpp"

namespace fleet::cli {

namespace {

constexpr double kFaultPeriodSim = 120.0;  // a fault every two simulated minutes
constexpr double kKillPauseWall = 2.0;     // a killed agent stays down this long
constexpr double kStallWall = 3.0;         // a stopped agent stays frozen this long
constexpr double kServerPauseWall = 1.0;   // a killed server stays down this long
/// Faults that fell behind their schedule (a map switch refused for a while) come one by one, this
/// far apart: a robot stalled while the server is down could not be found stalled.
constexpr double kFaultGapWall = kStallWall + 2.0;
// An obstacle switched on stays on this long: shorter than the 60 s deadlock window, so a robot
// whose every way it closes waits it out [Forklift thesis, Fig. 5.11] without counting as deadlocked.
constexpr double kObstacleOnSim = 45.0;

/// One injected fault and what it led to, in wall seconds from the injection.
struct FaultRecord {
  monitor::FaultKind kind;
  std::string target;
  double at_wall = 0.0;
  double at_sim = 0.0;
  std::int64_t order = 0;           ///< the robot's open order when it happened (agent faults)
  std::optional<double> detected;   ///< the server marked the robot lost
  std::optional<double> recovered;  ///< its order re-queued, failed with a reason, or ended
};

}  // namespace

int soak_command(const CommandArgs& command, std::ostream& out, std::ostream& err, std::uint32_t domain) {
  Args args(command.args);
  config::FleetConfig config = config::load_fleet_config(command.config_file);
  RunOptions options;
  options.kind = "soak";
  options.config_file = command.config_file;
  options.domain = domain;
  options.agents = static_cast<int>(args.integer("agents", 1, kMaxAgents).value_or(4));
  options.site = args.value("site").value_or(config.settings.get_string("site"));
  options.duration_s = args.number("duration", 1.0, 1e7).value_or(180.0);
  options.time_scale = args.number("time-scale", 0.01, 100.0).value_or(10.0);
  options.seed = args.integer("seed", 0, 2147483647).value_or(config.settings.get_int("seed"));
  options.http_port = static_cast<int>(args.integer("http-port", 0, 65535).value_or(0));
  options.agent_wrap = args.value("agent-wrap").value_or("");
  const std::string traffic =
      args.value("traffic").value_or(config.settings.get_bool("traffic.enabled") ? "on" : "off");
  if (traffic != "on" && traffic != "off") throw ArgError("--traffic '" + traffic + "': expected on or off");
  const auto kinds = monitor::parse_fault_list(args.value("faults").value_or("none"));
  std::vector<std::string> settings{"traffic.enabled=" + std::string(traffic == "on" ? "true" : "false")};
  while (auto v = args.value("set")) settings.push_back(*v);
  if (args.flag("verbose")) {
    // Debug logs of every process in the run directory: traffic requests, grants and waits.
    options.extra_server_args.push_back("--verbose");
    options.extra_agent_args.push_back("--verbose");
  }
  if (const auto rest = args.positionals(); !rest.empty()) throw ArgError("unexpected argument '" + rest[0] + "'");
  known_site_path(command.source_dir, options.site);
  // Checked here, named as given, before any process starts.
  for (const auto& s : settings) config::apply_set_flag(config, s);
  for (const auto& s : settings) {
    options.extra_server_args.insert(options.extra_server_args.end(), {"--set", s});
    options.extra_agent_args.insert(options.extra_agent_args.end(), {"--set", s});
  }
  {
    FleetClient probe(domain);
    if (probe.find_server(std::chrono::milliseconds(1200))) {
      throw ArgError("a fleet-server already runs on DDS domain " + std::to_string(domain) +
                     "; stop it or choose another --domain");
    }
  }
  const map::Site site = map::load_site(map::site_path(maps_dir(), options.site));
  std::vector<std::string> obstacle_ids;
  for (const auto& o : site.static_obstacles) obstacle_ids.push_back(o.id);

  // map-switch needs another map of the site to switch to (a revision: see map::site_revisions).
  const std::vector<std::string> site_maps = map::site_revisions(site);
  std::map<std::string, std::string> skipped;
  std::vector<monitor::FaultKind> active;
  for (auto k : kinds) {
    if (k == monitor::FaultKind::kMapSwitch && site_maps.size() < 2) {
      skipped[to_string(k)] = "site " + options.site + " has no other map in maps/ to switch to";
    } else if (k == monitor::FaultKind::kObstacles && obstacle_ids.empty()) {
      skipped[to_string(k)] = "site " + options.site + " has no designated obstacles";
    } else {
      active.push_back(k);
    }
  }
  const double duration_sim = options.duration_s * options.time_scale;
  auto plan = monitor::plan_faults(active, duration_sim, kFaultPeriodSim, 60.0, options.agents,
                                   static_cast<int>(obstacle_ids.size()), static_cast<std::uint64_t>(options.seed));

  install_stop_handlers();
  auto log = make_logger("fleetctl soak");
  FleetRun run(options, config, log);
  run.start();
  err << "Fleet soak: fleet-server and " << options.agents << " fleet-agents (" << model::join(run.robot_ids())
      << ") on DDS domain " << domain << ", site " << options.site << ", time scale " << options.time_scale
      << ", traffic " << traffic << ", " << plan.size() << " faults planned"
      << (kinds.empty() ? "" : " (" + std::to_string(kinds.size()) + " kinds)") << ", " << options.duration_s
      << " s wall.\n  logs: " << run.run_dir() << "/\n";
  for (const auto& [kind, why] : skipped) err << "  fault " << kind << " skipped: " << why << "\n";

  // The soak's own DDS reader of the server's view, for when it marks robots lost.
  FleetClient client(domain);
  dds::Reader<model::FleetView> view_reader(client.participant(), dds::qos::live_state());
  dds::Reader<model::OrderReport> report_reader(client.participant(), dds::qos::latched_state());
  std::map<std::string, bool> lost;
  std::vector<monitor::RobotLoss> losses;                 // every time the server took a robot for lost
  std::map<std::int64_t, std::set<std::string>> done_by;  // order -> robots that reported DONE

  // A fault carried out by the server (obstacles, maps): a refusal is logged, the run goes on.
  // The server's error, or "" when it took the command.
  auto command_server = [&client, &log](const std::string& verb, const std::string& target, const std::string& value) {
    model::Command c;
    c.verb = verb;
    c.target = target;
    c.value = value;
    const auto reply = client.send_command(c, std::chrono::milliseconds(3000));
    if (!reply || !reply->accepted) {
      const std::string error = reply ? reply->error : "no reply from the server";
      log->warn("{} {} {}: {}", verb, target, value, error);
      return error;
    }
    return std::string();
  };
  std::vector<FaultRecord> faults;
  std::size_t next_fault = 0;
  double retry_fault_at_wall = 0.0;  // a refused fault is tried again from then
  int fault_retries = 0;
  std::size_t current_map = 0;  // site_maps[0] is the site itself
  struct Pending {
    double at_wall;
    std::function<void()> action;
  };
  std::vector<Pending> pending;  // restarts, SIGCONTs, obstacles off
  auto index_of_agent = [&](int agent) { return static_cast<std::size_t>(agent) + 1; };

  // CPU per process from the first and last samples. Memory growth compares the low-water mark of
  // resident memory over the first eighth of the second half with that over the last eighth:
  // malloc hands freed memory back to the system in steps, so a single sample swings by several
  // percent of a 20 MB process, while a leak raises the low-water mark. A process restarted by a
  // fault is compared only once it is past its warm-up (maps, octree and DDS caches filling):
  // one restarted within the first eighth of the second half is left out rather than measured
  // from its own start.
  std::map<pid_t, Usage> first_usage, last_usage;
  std::map<pid_t, double> mid_low_kb, end_low_kb;
  std::map<pid_t, std::string> type_of;
  std::map<pid_t, double> first_seen_s;  // wall seconds into the run
  // An agent allocates as it first uses a part (a stacker's camera frames at its first docking):
  // it is measured once it has finished an order, from its robot's first DONE since the process
  // started (a restarted agent allocates afresh).
  std::map<pid_t, std::string> robot_of;
  std::map<std::string, std::vector<double>> done_s;  // wall seconds into the run, by robot
  const double warm_up_s = std::max(10.0, 0.1 * options.duration_s);
  auto sample = [&](std::map<pid_t, Usage>& into) {
    for (const auto& child : run.processes().children()) {
      if (!child.running) continue;
      type_of[child.pid] = child.name.starts_with("fleet-server") ? "server" : "agent";
      if (const auto space = child.name.find(' '); space != std::string::npos) {
        robot_of[child.pid] = child.name.substr(space + 1);
      }
      first_seen_s.emplace(child.pid, run.wall_seconds());
      if (auto u = usage_of(child.pid)) into[child.pid] = *u;
    }
  };
  sample(first_usage);
  last_usage = first_usage;
  double next_usage_sample = 1.0;
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
          losses.push_back({r.robot_id, now_wall, elapsed_sim});
          for (auto& f : faults) {
            if (f.target == r.robot_id && !f.detected &&
                (f.kind == monitor::FaultKind::kKillAgent || f.kind == monitor::FaultKind::kStallAgent)) {
              f.detected = now_wall - f.at_wall;
            }
          }
        }
        lost[r.robot_id] = is_lost;
      }
    });
    report_reader.take_data([&](model::OrderReport&& report) {
      if (report.status == "DONE") {
        done_by[report.order_id].insert(report.robot_id);
        done_s[report.robot_id].push_back(run.wall_seconds());
      }
    });
    for (auto& f : faults) {
      if (f.recovered || f.order == 0) continue;
      auto it = run.orders().find(f.order);
      if (it == run.orders().end()) continue;
      const auto& info = it->second;
      // Recovered: the order is back in the queue, or ended (failed with its reason, or done),
      // or running again on a robot that is not lost: another one, or its own robot that was
      // found lost and is back (a robot lost with the pallet keeps its order).
      const bool requeued = info.state == "QUEUED" || info.state == "DONE" || info.state == "FAILED" ||
                            info.state == "CANCELLED" || (info.robot_id != f.target && !info.robot_id.empty());
      const bool resumed = f.detected && !lost[f.target] && info.robot_id == f.target;
      if (requeued || resumed) f.recovered = now_wall - f.at_wall;
    }

    for (auto it = pending.begin(); it != pending.end();) {
      if (now_wall >= it->at_wall) {
        it->action();
        it = pending.erase(it);
      } else {
        ++it;
      }
    }

    while (next_fault < plan.size() && plan[next_fault].at_sim <= elapsed_sim && now_wall >= retry_fault_at_wall) {
      const auto& fault = plan[next_fault++];
      FaultRecord record{fault.kind, "", now_wall, elapsed_sim, 0, std::nullopt, std::nullopt};
      auto open_order_of = [&](const std::string& robot) -> std::int64_t {
        for (const auto& [id, info] : run.orders()) {
          if ((info.state == "ASSIGNED" || info.state == "ACTIVE") && info.robot_id == robot) return id;
        }
        return 0;
      };
      switch (fault.kind) {
        case monitor::FaultKind::kKillAgent: {
          const std::size_t child = index_of_agent(fault.target);
          record.target = run.robot_ids()[static_cast<std::size_t>(fault.target)];
          if (!run.processes().children()[child].running) continue;
          record.order = open_order_of(record.target);
          run.expect_exit(child);
          run.processes().signal(child, SIGKILL);
          run.forget_progress(record.target);
          pending.push_back({now_wall + kKillPauseWall, [&run, child, robot = record.target] {
                               run.processes().restart(child);
                               run.forget_progress(robot);
                             }});
          break;
        }
        case monitor::FaultKind::kStallAgent: {
          const std::size_t child = index_of_agent(fault.target);
          record.target = run.robot_ids()[static_cast<std::size_t>(fault.target)];
          if (!run.processes().children()[child].running) continue;
          record.order = open_order_of(record.target);
          run.processes().signal(child, SIGSTOP);
          run.forget_progress(record.target);
          pending.push_back({now_wall + kStallWall, [&run, child, robot = record.target] {
                               run.processes().signal(child, SIGCONT);
                               run.forget_progress(robot);
                             }});
          break;
        }
        case monitor::FaultKind::kKillServer: {
          record.target = "fleet-server";
          run.expect_exit(FleetRun::kServerIndex);
          run.processes().signal(FleetRun::kServerIndex, SIGKILL);
          pending.push_back({now_wall + kServerPauseWall, [&run] { run.processes().restart(FleetRun::kServerIndex); }});
          break;
        }
        case monitor::FaultKind::kObstacles: {
          // The server refuses an obstacle over a robot: the next one of the site is tried.
          for (std::size_t k = 0; k < obstacle_ids.size() && record.target.empty(); ++k) {
            const std::string& id = obstacle_ids[(static_cast<std::size_t>(fault.target) + k) % obstacle_ids.size()];
            if (command_server("obstacle", id, "on").empty()) record.target = id;
          }
          if (record.target.empty()) continue;
          pending.push_back({now_wall + kObstacleOnSim / options.time_scale,
                             [&command_server, id = record.target] { command_server("obstacle", id, "off"); }});
          break;
        }
        case monitor::FaultKind::kMapSwitch: {
          // Every robot onto the next map of the site, round the list. The server refuses while a
          // robot stands on a road the next map closes: try again each wall second, for a while.
          constexpr int kMaxRetries = 20;
          const std::string& next_map = site_maps[(current_map + 1) % site_maps.size()];
          if (!command_server("map", "", next_map).empty()) {
            if (++fault_retries <= kMaxRetries) {
              --next_fault;
              retry_fault_at_wall = now_wall + 1.0;
            } else {
              log->warn("fault {}: map-switch to {} given up after {} refusals", faults.size() + 1, next_map,
                        kMaxRetries);
              fault_retries = 0;
            }
            continue;
          }
          fault_retries = 0;
          current_map = (current_map + 1) % site_maps.size();
          record.target = next_map;
          break;
        }
      }
      log->warn("fault {}: {} at t={:.0f} s sim{}", faults.size() + 1, to_string(fault.kind), elapsed_sim,
                record.target.empty() ? "" : " (" + record.target + ")");
      faults.push_back(record);
      retry_fault_at_wall = now_wall + kFaultGapWall;
    }

    if (elapsed >= next_usage_sample) {
      std::map<pid_t, Usage> now_usage;
      sample(now_usage);
      for (const auto& [pid, u] : now_usage) last_usage[pid] = u;
      next_usage_sample += 1.0;
      const double fraction = elapsed / options.duration_s;
      auto low_water = [&](std::map<pid_t, double>& into) {
        for (const auto& [pid, u] : now_usage) {
          if (u.rss_kb <= 0.0 || run.wall_seconds() - first_seen_s[pid] < warm_up_s) continue;
          if (type_of[pid] == "agent") {
            const std::vector<double>& done = done_s[robot_of[pid]];
            const auto first = std::lower_bound(done.begin(), done.end(), first_seen_s[pid]);
            if (first == done.end() || run.wall_seconds() - *first < warm_up_s) continue;
          }
          auto [it, fresh] = into.emplace(pid, u.rss_kb);
          if (!fresh) it->second = std::min(it->second, u.rss_kb);
        }
      };
      if (fraction >= 0.5 && fraction < 0.625) low_water(mid_low_kb);
      if (fraction >= 0.875) low_water(end_low_kb);
    }
    if (run.wall_seconds() >= next_progress) {
      const auto t = run.tally();
      err << "  t=" << static_cast<int>(run.sim_seconds()) << " s sim: " << t.done << " orders done, " << t.open
          << " open, " << t.failed << " failed, " << run.collisions().size() << " collisions, "
          << run.progress().deadlocks().size() << " deadlocks, " << faults.size() << " faults\n";
      next_progress += 10.0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  // Faults still pending (a stopped agent, a server down) are undone before the end.
  for (auto& p : pending) p.action();
  sample(last_usage);
  const double wall = run.wall_seconds();
  run.stop();

  // ---- summary ---------------------------------------------------------------------------
  const auto tally = run.tally();
  const auto stats = monitor::order_stats(run.orders(), run.start_sim() + run.sim_seconds());
  long duplicated = 0;
  for (const auto& [id, info] : run.orders()) {
    long dones = 0;
    for (const auto& e : info.history) dones += e.state == "DONE" ? 1 : 0;
    const auto by = done_by.find(id);
    if (dones > 1 || (by != done_by.end() && by->second.size() > 1)) ++duplicated;
  }
  std::vector<double> detect, recover;
  long undetected = 0;
  nlohmann::json fault_list = nlohmann::json::array();
  for (const auto& f : faults) {
    const bool agent_fault = f.kind == monitor::FaultKind::kKillAgent || f.kind == monitor::FaultKind::kStallAgent;
    if (agent_fault) {
      if (f.detected) {
        detect.push_back(*f.detected);
      } else {
        ++undetected;
      }
    }
    if (f.recovered) recover.push_back(*f.recovered);
    nlohmann::json j{{"kind", to_string(f.kind)}, {"target", f.target}, {"at_sim_s", round_to(f.at_sim, 0.1)}};
    if (f.order) j["order"] = f.order;
    if (f.detected) j["detected_s"] = round_to(*f.detected, 0.001);
    if (f.recovered) j["recovered_s"] = round_to(*f.recovered, 0.001);
    fault_list.push_back(j);
  }
  // A robot lost with no fault behind it: a process that stood still or a link that broke.
  std::vector<monitor::InjectedFault> injected;
  for (const auto& f : faults) injected.push_back({f.kind, f.target, f.at_wall});
  constexpr double kLossAfterFaultWall = kKillPauseWall + kStallWall + 5.0;
  nlohmann::json unexplained = nlohmann::json::array();
  std::vector<std::string> unexplained_text;
  for (const auto& loss : monitor::unexplained_losses(losses, injected, kLossAfterFaultWall)) {
    unexplained.push_back({{"robot", loss.robot_id}, {"sim_s", round_to(loss.at_sim, 0.1)}});
    unexplained_text.push_back(fmt::format("{} at {:.0f} s sim", loss.robot_id, loss.at_sim));
  }
  // Memory growth over the second half (the worst process of each type, and how many were
  // measured) and CPU over the run, per process type.
  std::map<std::string, double> growth, cpu_s, alive_s;
  std::map<std::string, int> measured;
  for (const auto& [pid, end_kb] : end_low_kb) {
    const std::string& type = type_of[pid];
    if (auto mid = mid_low_kb.find(pid); mid != mid_low_kb.end()) {
      growth[type] =
          std::max(growth.contains(type) ? growth[type] : -100.0, 100.0 * (end_kb - mid->second) / mid->second);
      ++measured[type];
    }
  }
  // CPU: what every process of a type used (a killed one up to its last sample), shared over
  // the type's slots (1 server, N agents) for the whole run: percent of one core per process.
  for (const auto& [pid, type] : type_of) {
    const auto begin = first_usage.find(pid);
    cpu_s[type] += last_usage[pid].cpu_s - (begin != first_usage.end() ? begin->second.cpu_s : 0.0);
  }
  alive_s["server"] = wall;
  alive_s["agent"] = wall * options.agents;
  nlohmann::json growth_json = nlohmann::json::object(), cpu_json = nlohmann::json::object();
  nlohmann::json measured_json = nlohmann::json::object();
  for (const auto& [type, g] : growth) growth_json[type] = round_to(g, 0.1);
  for (const auto& [type, n] : measured) measured_json[type] = n;
  for (const auto& [type, c] : cpu_s) cpu_json[type] = round_to(100.0 * c / std::max(1e-9, alive_s[type]), 0.1);
  double worst_growth = 0.0;
  for (const auto& [type, g] : growth) worst_growth = std::max(worst_growth, g);

  nlohmann::json collisions = nlohmann::json::array();
  for (const auto& c : run.collisions()) {
    if (collisions.size() >= 10) break;
    collisions.push_back({{"sim_s", round_to(c.sim_time - run.start_sim(), 0.01)},
                          {"robots", {c.robot_a, c.robot_b}},
                          {"a", {round_to(c.pose_a.x, 0.001), round_to(c.pose_a.y, 0.001)}},
                          {"b", {round_to(c.pose_b.x, 0.001), round_to(c.pose_b.y, 0.001)}}});
  }
  nlohmann::json deadlocks = nlohmann::json::array();
  for (const auto& d : run.progress().deadlocks()) {
    deadlocks.push_back({{"robot", d.robot_id},
                         {"task", d.task},
                         {"since_sim_s", round_to(d.since - run.start_sim(), 0.1)},
                         {"at", {round_to(d.pose.x, 0.001), round_to(d.pose.y, 0.001)}}});
  }
  const double now_sim = run.start_sim() + run.sim_seconds();
  const auto done_by_kind = monitor::done_by_kind(run.orders(), tally.first_id);
  nlohmann::json localization = nlohmann::json::object();
  for (const auto& [fleet, e] : run.localization_by_fleet()) {
    localization[fleet] = {{"p95_m", round_to(e.p95, 0.001)}, {"max_m", round_to(e.max, 0.001)}};
  }
  // The robot whose estimate strayed furthest: where and when, to read its log there.
  nlohmann::json worst_localization = nlohmann::json::object();
  const auto& worst = run.localization().worst();
  if (const auto w = std::max_element(worst.begin(), worst.end(),
                                      [](const auto& a, const auto& b) { return a.second.error < b.second.error; });
      w != worst.end()) {
    const auto& [robot, e] = *w;
    worst_localization = {{"robot", robot},
                          {"error_m", round_to(e.error, 0.001)},
                          {"sim_s", round_to(e.sim_time - run.start_sim(), 0.1)},
                          {"truth", {round_to(e.truth.x, 0.001), round_to(e.truth.y, 0.001)}},
                          {"estimate", {round_to(e.estimate.x, 0.001), round_to(e.estimate.y, 0.001)}}};
  }
  // Two pickers working one aisle, one along each face [Picker thesis, section 4.3.3.1].
  nlohmann::json aisle_share = nlohmann::json::object();
  if (const auto* share = run.aisle_share()) {
    aisle_share = {{"seconds", round_to(share->shared_seconds(), 0.1)},
                   {"times", share->times()},
                   {"longest_s", round_to(share->longest_seconds(), 0.1)},
                   {"longest_aisle", share->longest_aisle()},
                   {"longest_robots", share->longest_robots()}};
  }
  // The agent whose control steps ran latest against the clock.
  const auto lag = run.worst_control_lag();
  const nlohmann::json control_lag = control_lag_json(lag);
  nlohmann::json lag_by_fleet = nlohmann::json::object();
  for (const auto& [fleet, p99] : run.control_lag_p99_by_fleet()) lag_by_fleet[fleet] = round_to(p99, 0.0001);
  nlohmann::json summary{{"orders_created", tally.created},
                         {"orders_done", tally.done},
                         {"orders_failed", tally.failed},
                         {"orders_open", tally.open},
                         {"orders_lost", tally.lost},
                         {"orders_done_by_fleet", run.done_by_fleet()},
                         {"orders_done_by_kind", done_by_kind},
                         {"localization_error", localization},
                         {"localization_worst", worst_localization},
                         {"pickers_sharing_an_aisle", aisle_share},
                         {"orders_duplicated", duplicated},
                         {"collisions", run.collisions().size()},
                         {"deadlocks", run.progress().deadlocks().size()},
                         {"max_wait_s", round_to(run.progress().max_wait_s(now_sim), 0.1)},
                         {"order_time_mean_s", round_to(stats.order_time_mean_s, 0.1)},
                         {"order_time_p95_s", round_to(stats.order_time_p95_s, 0.1)},
                         {"sim_seconds", round_to(run.sim_seconds(), 0.1)},
                         {"wall_seconds", round_to(wall, 0.1)},
                         {"agents", options.agents},
                         {"site", options.site},
                         {"traffic", traffic},
                         {"seed", options.seed},
                         {"time_scale", options.time_scale},
                         {"faults_injected", faults.size()},
                         {"faults_undetected", undetected},
                         {"robots_lost_without_a_fault", unexplained},
                         {"detect_latency_p95_s", round_to(common::percentile(detect, 0.95), 0.001)},
                         {"recovery_p95_s", round_to(common::percentile(recover, 0.95), 0.001)},
                         {"rss_growth_pct", growth_json},
                         {"rss_measured_processes", measured_json},
                         {"cpu_pct", cpu_json},
                         {"control_lag_worst", control_lag},
                         {"control_lag_p99_by_fleet", lag_by_fleet},
                         {"crashed", run.crashes()},
                         {"faults", fault_list},
                         {"faults_skipped", skipped},
                         {"collision_list", collisions},
                         {"deadlock_list", deadlocks},
                         {"run_dir", run.run_dir()}};
  std::vector<std::string> failures;
  if (tally.lost != 0) failures.push_back(std::to_string(tally.lost) + " orders lost");
  if (duplicated != 0) failures.push_back(std::to_string(duplicated) + " orders done twice");
  if (!run.collisions().empty()) failures.push_back(std::to_string(run.collisions().size()) + " collisions");
  if (!run.progress().deadlocks().empty())
    failures.push_back(std::to_string(run.progress().deadlocks().size()) + " deadlocks");
  if (!run.crashes().empty()) failures.push_back("crashed: " + model::join(run.crashes()));
  if (undetected != 0) failures.push_back(std::to_string(undetected) + " agent faults never detected");
  if (!unexplained_text.empty()) failures.push_back("lost with no fault: " + model::join(unexplained_text, ", "));
  if (worst_growth > 10.0) failures.push_back("memory grew " + std::to_string(static_cast<int>(worst_growth)) + " %");
  // In real time only: at a higher time scale the host runs every agent that many times faster
  // than its robot would, and the figures say how far it falls short, not whether a robot would.
  if (lag && options.time_scale <= 1.0 && lag->p99_s > lag->period_s) {
    failures.push_back(fmt::format("agent {} behind the clock: control steps {:.1f} ms late at p99, period {:.1f} ms",
                                   lag->robot, 1000.0 * lag->p99_s, 1000.0 * lag->period_s));
  }
  summary["failures"] = failures;
  // Kept with the logs and tracks, so a run read back later still has its figures.
  std::ofstream(run.run_dir() + "/summary.json") << summary.dump(2) << "\n";
  if (command.json) {
    out << summary.dump() << "\n";
  } else {
    out << "Fleet soak summary (" << summary["sim_seconds"] << " s sim, " << summary["wall_seconds"]
        << " s wall, traffic " << traffic << ")\n"
        << "  orders: " << tally.created << " created, " << tally.done << " done, " << tally.failed << " failed, "
        << tally.open << " open, " << tally.lost << " lost, " << duplicated << " done twice\n"
        << "  done per fleet: " << fleet_counts(run.done_by_fleet()) << "; per kind: " << fleet_counts(done_by_kind)
        << "\n"
        << "  order time: mean " << summary["order_time_mean_s"] << " s, p95 " << summary["order_time_p95_s"]
        << " s sim; longest wait " << summary["max_wait_s"] << " s\n"
        << "  localization error (estimate against truth): " << localization.dump() << "\n"
        << "  pickers sharing an aisle: " << aisle_share.dump() << "\n"
        << "  collisions: " << run.collisions().size() << ", deadlocks: " << run.progress().deadlocks().size() << "\n"
        << "  faults: " << faults.size() << " injected, detection p95 " << summary["detect_latency_p95_s"]
        << " s, recovery p95 " << summary["recovery_p95_s"] << " s; robots lost with no fault: " << unexplained.size()
        << "\n"
        << "  memory growth (second half): " << growth_json.dump() << " % over " << measured_json.dump()
        << " processes, CPU: " << cpu_json.dump() << " % of a core\n"
        << "  control lag (worst agent, sim s): " << control_lag.dump() << "\n"
        << "  " << (failures.empty() ? "PASS" : "FAIL: " + model::join(failures, "; ")) << "\n"
        << "  logs: " << run.run_dir() << "/\n";
  }
  return failures.empty() ? kExitOk : kExitFailed;
}

}  // namespace fleet::cli
