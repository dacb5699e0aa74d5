// `fleetctl soak`'s summary: its figures as JSON, the reasons it fails, and the text it prints.

#include <algorithm>
#include <fstream>
#include <ostream>

#include "cli/soak_parts.hpp"
#include "common/percentile.hpp"
#include "model/names.hpp"
#include "monitor/order_accounting.hpp"

namespace fleet::cli {

namespace {

long orders_done_twice(const FleetRun& run, const std::map<std::int64_t, std::set<std::string>>& done_by) {
  long duplicated = 0;
  for (const auto& [id, info] : run.orders()) {
    long dones = 0;
    for (const auto& e : info.history) dones += e.state == "DONE" ? 1 : 0;
    const auto by = done_by.find(id);
    if (dones > 1 || (by != done_by.end() && by->second.size() > 1)) ++duplicated;
  }
  return duplicated;
}

/// The faults as JSON, with the p95 of detection and recovery, the faults never detected, the
/// failovers of kill-host (from the kill to grants from the server that took over) and the
/// restarts of kill-server (to grants from the server restarted).
nlohmann::json fault_figures(const std::vector<FaultRecord>& faults) {
  std::vector<double> detect, recover, failover, restart;
  long undetected = 0;
  nlohmann::json list = nlohmann::json::array();
  for (const auto& f : faults) {
    if (f.to_detect()) {
      if (f.detected) {
        (f.on_agent() ? detect : failover).push_back(*f.detected);
      } else {
        ++undetected;
      }
    }
    if (f.kind == monitor::FaultKind::kKillServer && f.detected) restart.push_back(*f.detected);
    if (f.recovered) recover.push_back(*f.recovered);
    nlohmann::json j{{"kind", to_string(f.kind)}, {"target", f.target}, {"at_sim_s", round_to(f.at_sim, 0.1)}};
    if (f.order) j["order"] = f.order;
    if (f.detected) j["detected_s"] = round_to(*f.detected, 0.001);
    if (f.recovered) j["recovered_s"] = round_to(*f.recovered, 0.001);
    list.push_back(j);
  }
  return {{"faults_injected", faults.size()},
          {"faults_undetected", undetected},
          {"detect_latency_p95_s", round_to(common::percentile(detect, 0.95), 0.001)},
          {"recovery_p95_s", round_to(common::percentile(recover, 0.95), 0.001)},
          {"failovers", failover.size()},
          {"failover_median_s", round_to(common::percentile(failover, 0.5), 0.001)},
          {"failover_p95_s", round_to(common::percentile(failover, 0.95), 0.001)},
          {"restarts", restart.size()},
          {"restart_median_s", round_to(common::percentile(restart, 0.5), 0.001)},
          {"restart_p95_s", round_to(common::percentile(restart, 0.95), 0.001)},
          {"faults", list}};
}

nlohmann::json picking_json(const monitor::PickingFigures& f) {
  return {{"pick_orders_done", f.pick_orders_done},
          {"loader_jobs_done", f.loader_jobs_done},
          {"boxes_picked", f.boxes_picked},
          {"boxes_loaded", f.boxes_loaded},
          {"picker_hours", round_to(f.picker_hours, 0.001)},
          {"items_per_picker_hour", round_to(f.items_per_hour, 0.1)}};
}

/// Robots lost with no fault behind them: a process that stood still or a link that broke.
std::vector<monitor::RobotLoss> unexplained_losses(const SoakObservations& seen) {
  std::vector<monitor::InjectedFault> injected;
  for (const auto& f : *seen.faults) injected.push_back({f.kind, f.target, f.at_wall});
  constexpr double kLossAfterFaultWall = SoakFaults::kKillPauseWall + SoakFaults::kStallWall + 5.0;
  return monitor::unexplained_losses(seen.losses, injected, kLossAfterFaultWall);
}

nlohmann::json losses_json(const std::vector<monitor::RobotLoss>& losses) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& loss : losses) list.push_back({{"robot", loss.robot_id}, {"sim_s", round_to(loss.at_sim, 0.1)}});
  return list;
}

nlohmann::json collisions_and_deadlocks(const FleetRun& run) {
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
  return {{"collisions", run.collisions().size()},
          {"deadlocks", run.progress().deadlocks().size()},
          {"collision_list", collisions},
          {"deadlock_list", deadlocks}};
}

/// Each fleet's localization error with its robot whose estimate strayed furthest, and that of
/// the whole run: where and when, to read its log there.
nlohmann::json localization_figures(const FleetRun& run) {
  const auto& worst = run.localization().worst();
  const auto describe = [&](const std::string& robot, const auto& e) {
    return nlohmann::json{{"robot", robot},
                          {"error_m", round_to(e.error, 0.001)},
                          {"sim_s", round_to(e.sim_time - run.start_sim(), 0.1)},
                          {"truth", {round_to(e.truth.x, 0.001), round_to(e.truth.y, 0.001)}},
                          {"estimate", {round_to(e.estimate.x, 0.001), round_to(e.estimate.y, 0.001)}}};
  };
  nlohmann::json localization = nlohmann::json::object();
  for (const auto& [fleet, e] : run.localization_by_fleet()) {
    localization[fleet] = {{"p95_m", round_to(e.p95, 0.001)}, {"max_m", round_to(e.max, 0.001)}};
    const auto fleet_worst = std::max_element(worst.begin(), worst.end(), [&](const auto& a, const auto& b) {
      const bool a_in = run.fleet_of(a.first) == fleet, b_in = run.fleet_of(b.first) == fleet;
      return a_in != b_in ? b_in : a.second.error < b.second.error;
    });
    if (fleet_worst != worst.end() && run.fleet_of(fleet_worst->first) == fleet) {
      localization[fleet]["worst"] = describe(fleet_worst->first, fleet_worst->second);
    }
  }
  nlohmann::json worst_localization = nlohmann::json::object();
  if (const auto w = std::max_element(worst.begin(), worst.end(),
                                      [](const auto& a, const auto& b) { return a.second.error < b.second.error; });
      w != worst.end()) {
    worst_localization = describe(w->first, w->second);
  }
  return {{"localization_error", localization}, {"localization_worst", worst_localization}};
}

/// Two pickers working one aisle, one along each face [Picker thesis, section 4.3.3.1].
nlohmann::json aisle_share_figures(const FleetRun& run) {
  nlohmann::json aisle_share = nlohmann::json::object();
  if (const auto* share = run.aisle_share()) {
    aisle_share = {{"seconds", round_to(share->shared_seconds(), 0.1)},
                   {"times", share->times()},
                   {"longest_s", round_to(share->longest_seconds(), 0.1)},
                   {"longest_aisle", share->longest_aisle()},
                   {"longest_robots", share->longest_robots()}};
  }
  return aisle_share;
}

std::vector<std::string> failures_of(const FleetRun& run, const RunOptions& options, const nlohmann::json& s,
                                     const std::vector<monitor::RobotLoss>& unexplained_losses, double worst_growth) {
  std::vector<std::string> failures;
  const long lost = s["orders_lost"], duplicated = s["orders_duplicated"], undetected = s["faults_undetected"];
  if (lost != 0) failures.push_back(std::to_string(lost) + " orders lost");
  if (duplicated != 0) failures.push_back(std::to_string(duplicated) + " orders done twice");
  if (!run.collisions().empty()) failures.push_back(std::to_string(run.collisions().size()) + " collisions");
  if (!run.progress().deadlocks().empty())
    failures.push_back(std::to_string(run.progress().deadlocks().size()) + " deadlocks");
  if (!run.crashes().empty()) failures.push_back("crashed: " + model::join(run.crashes()));
  if (undetected != 0) failures.push_back(std::to_string(undetected) + " faults never detected");
  std::vector<std::string> unexplained;
  for (const auto& loss : unexplained_losses) {
    unexplained.push_back(fmt::format("{} at {:.0f} s sim", loss.robot_id, loss.at_sim));
  }
  if (!unexplained.empty()) failures.push_back("lost with no fault: " + model::join(unexplained, ", "));
  if (worst_growth > 10.0) failures.push_back("memory grew " + std::to_string(static_cast<int>(worst_growth)) + " %");
  // In real time only: at a higher time scale the host runs every agent that many times faster
  // than its robot would, and the figures say how far it falls short, not whether a robot would.
  const auto lag = run.worst_control_lag();
  if (lag && options.time_scale <= 1.0 && lag->p99_s > lag->period_s) {
    failures.push_back(fmt::format("agent {} behind the clock: control steps {:.1f} ms late at p99, period {:.1f} ms",
                                   lag->robot, 1000.0 * lag->p99_s, 1000.0 * lag->period_s));
  }
  return failures;
}

}  // namespace

nlohmann::json soak_summary(const FleetRun& run, const RunOptions& options, const SoakObservations& seen) {
  const auto tally = run.tally();
  const double now_sim = run.start_sim() + run.sim_seconds();
  const auto stats = monitor::order_stats(run.orders(), now_sim);
  const std::vector<monitor::RobotLoss> unexplained = unexplained_losses(seen);
  nlohmann::json lag_by_fleet = nlohmann::json::object();
  for (const auto& [fleet, p99] : run.control_lag_p99_by_fleet()) lag_by_fleet[fleet] = round_to(p99, 0.0001);
  nlohmann::json summary{{"orders_created", tally.created},
                         {"orders_done", tally.done},
                         {"orders_failed", tally.failed},
                         {"orders_open", tally.open},
                         {"orders_lost", tally.lost},
                         {"orders_done_by_fleet", run.done_by_fleet()},
                         {"orders_done_by_kind", monitor::done_by_kind(run.orders(), tally.first_id)},
                         {"pickers_sharing_an_aisle", aisle_share_figures(run)},
                         {"picking", picking_json(monitor::picking_figures(run.orders(), tally.first_id))},
                         {"orders_duplicated", orders_done_twice(run, seen.done_by)},
                         {"max_wait_s", round_to(run.progress().max_wait_s(now_sim), 0.1)},
                         {"order_time_mean_s", round_to(stats.order_time_mean_s, 0.1)},
                         {"order_time_p95_s", round_to(stats.order_time_p95_s, 0.1)},
                         {"sim_seconds", round_to(run.sim_seconds(), 0.1)},
                         {"wall_seconds", round_to(seen.wall, 0.1)},
                         {"agents", options.agents},
                         {"site", options.site},
                         {"traffic", seen.traffic},
                         {"seed", options.seed},
                         {"time_scale", options.time_scale},
                         {"robots_lost_without_a_fault", losses_json(unexplained)},
                         {"rss_growth_pct", seen.usage.growth_pct},
                         {"rss_measured_processes", seen.usage.measured},
                         {"cpu_pct", seen.usage.cpu_pct},
                         {"control_lag_worst", control_lag_json(run.worst_control_lag())},
                         {"control_lag_p99_by_fleet", lag_by_fleet},
                         {"crashed", run.crashes()},
                         {"faults_skipped", seen.faults_skipped},
                         {"refused_samples", seen.refused_samples},
                         {"run_dir", run.run_dir()}};
  // What fleet-vda5050 cost and how fast it passed grants on, when the run had VDA 5050 vehicles.
  if (std::ifstream figures(run.run_dir() + "/vda5050-figures.json"); figures) {
    summary["vda5050_bridge"] = nlohmann::json::parse(figures, nullptr, false);
  }
  summary.update(fault_figures(*seen.faults));
  summary.update(collisions_and_deadlocks(run));
  summary.update(localization_figures(run));
  summary["failures"] = failures_of(run, options, summary, unexplained, seen.usage.worst_growth);
  return summary;
}

void print_soak_summary(std::ostream& out, const FleetRun& run, const nlohmann::json& s) {
  const std::vector<std::string> failures = s["failures"];
  out << "Fleet soak summary (" << s["sim_seconds"] << " s sim, " << s["wall_seconds"] << " s wall, traffic "
      << s["traffic"].get<std::string>() << ")\n"
      << "  orders: " << s["orders_created"] << " created, " << s["orders_done"] << " done, " << s["orders_failed"]
      << " failed, " << s["orders_open"] << " open, " << s["orders_lost"] << " lost, " << s["orders_duplicated"]
      << " done twice\n"
      << "  done per fleet: " << fleet_counts(run.done_by_fleet())
      << "; per kind: " << fleet_counts(s["orders_done_by_kind"].get<std::map<std::string, long>>()) << "\n"
      << "  order time: mean " << s["order_time_mean_s"] << " s, p95 " << s["order_time_p95_s"]
      << " s sim; longest wait " << s["max_wait_s"] << " s\n"
      << "  localization error (estimate against truth): " << s["localization_error"].dump() << "\n"
      << "  picking: " << s["picking"]["items_per_picker_hour"] << " items an hour per working picker ("
      << s["picking"]["boxes_picked"] << " boxes in " << s["picking"]["pick_orders_done"] << " pick orders, "
      << s["picking"]["loader_jobs_done"] << " of them loader jobs with " << s["picking"]["boxes_loaded"]
      << " boxes loaded)\n"
      << "  pickers sharing an aisle: " << s["pickers_sharing_an_aisle"].dump() << "\n"
      << "  collisions: " << s["collisions"] << ", deadlocks: " << s["deadlocks"] << "\n"
      << "  faults: " << s["faults_injected"] << " injected, detection p95 " << s["detect_latency_p95_s"]
      << " s, recovery p95 " << s["recovery_p95_s"] << " s; failovers " << s["failovers"] << ", median "
      << s["failover_median_s"] << " s, p95 " << s["failover_p95_s"] << " s; restarts " << s["restarts"] << ", median "
      << s["restart_median_s"] << " s, p95 " << s["restart_p95_s"]
      << " s; robots lost with no fault: " << s["robots_lost_without_a_fault"].size() << "\n"
      << "  memory growth (second half): " << s["rss_growth_pct"].dump() << " % over "
      << s["rss_measured_processes"].dump() << " processes, CPU: " << s["cpu_pct"].dump() << " % of a core\n"
      << "  control lag (worst agent, sim s): " << s["control_lag_worst"].dump() << "\n"
      << "  " << (failures.empty() ? "PASS" : "FAIL: " + model::join(failures, "; ")) << "\n"
      << "  logs: " << run.run_dir() << "/\n";
}

}  // namespace fleet::cli
