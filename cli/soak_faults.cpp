// `fleetctl soak`'s faults on their schedule and its measurement of the processes.

#include <signal.h>

#include <algorithm>

#include "cli/soak_parts.hpp"
#include "model/messages.hpp"

namespace fleet::cli {

namespace {

constexpr double kServerPauseWall = 1.0;  // a killed server stays down this long
/// Faults that fell behind their schedule (a map switch refused for a while) come one by one, this
/// far apart: a robot stalled while the server is down could not be found stalled.
constexpr double kFaultGapWall = SoakFaults::kStallWall + 2.0;
// An obstacle switched on stays on this long: shorter than the 60 s deadlock window, so a robot
// whose every way it closes waits it out [Forklift thesis, Fig. 5.11] without counting as deadlocked.
constexpr double kObstacleOnSim = 45.0;
// A map switch the server refuses (a robot stands on a road the next map closes) is tried again
// each wall second, this many times.
constexpr int kMaxMapRetries = 20;

std::size_t index_of_agent(int agent) {
  return static_cast<std::size_t>(agent) + 1;
}

}  // namespace

SoakFaults::SoakFaults(FleetRun& run, FleetClient& client, Logger log, std::vector<monitor::ScheduledFault> plan,
                       std::vector<std::string> obstacle_ids, std::vector<std::string> site_maps, double time_scale)
    : run_(run),
      client_(client),
      log_(std::move(log)),
      plan_(std::move(plan)),
      obstacle_ids_(std::move(obstacle_ids)),
      site_maps_(std::move(site_maps)),
      time_scale_(time_scale) {}

void SoakFaults::robot_lost(const std::string& robot, double now_wall) {
  for (auto& f : faults_) {
    if (f.target == robot && !f.detected && f.on_agent()) f.detected = now_wall - f.at_wall;
  }
}

void SoakFaults::follow_recovery(const std::map<std::string, bool>& lost, double now_wall) {
  for (auto& f : faults_) {
    const bool server_fault = f.kind == monitor::FaultKind::kKillHost || f.kind == monitor::FaultKind::kKillServer;
    if (server_fault && !f.detected) {
      // Served again once grants come from a DDS writer not heard before the kill: the server that
      // took over, or the one restarted.
      if (const auto flowing = run_.grants_from_a_new_writer_since(f.at_wall)) {
        f.detected = *flowing - f.at_wall;
        if (f.kind == monitor::FaultKind::kKillHost) f.recovered = f.detected;
      }
    }
    if (f.recovered || f.order == 0) continue;
    auto it = run_.orders().find(f.order);
    if (it == run_.orders().end()) continue;
    const auto& info = it->second;
    // Recovered: the order is back in the queue, or ended (failed with its reason, or done),
    // or running again on a robot that is not lost: another one, or its own robot that was
    // found lost and is back (a robot lost with the pallet keeps its order).
    const bool requeued = info.state == "QUEUED" || info.state == "DONE" || info.state == "FAILED" ||
                          info.state == "CANCELLED" || (info.robot_id != f.target && !info.robot_id.empty());
    const auto robot_lost = lost.find(f.target);
    const bool back = robot_lost == lost.end() || !robot_lost->second;
    const bool resumed = f.detected && back && info.robot_id == f.target;
    if (requeued || resumed) f.recovered = now_wall - f.at_wall;
  }
}

void SoakFaults::step(double now_wall, double elapsed_sim) {
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (now_wall >= it->at_wall) {
      it->action();
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
  while (next_fault_ < plan_.size() && plan_[next_fault_].at_sim <= elapsed_sim && now_wall >= retry_fault_at_wall_) {
    const auto& fault = plan_[next_fault_++];
    FaultRecord record{fault.kind, "", now_wall, elapsed_sim, 0, std::nullopt, std::nullopt};
    bool retry = false;
    if (!inject(fault, record, now_wall, retry)) {
      if (retry) {
        --next_fault_;
        retry_fault_at_wall_ = now_wall + 1.0;
      }
      continue;
    }
    log_->warn("fault {}: {} at t={:.0f} s sim{}", faults_.size() + 1, to_string(fault.kind), elapsed_sim,
               record.target.empty() ? "" : " (" + record.target + ")");
    faults_.push_back(record);
    retry_fault_at_wall_ = now_wall + kFaultGapWall;
  }
}

bool SoakFaults::inject(const monitor::ScheduledFault& fault, FaultRecord& record, double now_wall, bool& retry) {
  switch (fault.kind) {
    case monitor::FaultKind::kKillAgent:
    case monitor::FaultKind::kStallAgent:
      return inject_agent_fault(fault, record, now_wall);
    case monitor::FaultKind::kKillServer:
      record.target = "fleet-server";
      run_.expect_exit(FleetRun::kServerIndex);
      run_.processes().signal(FleetRun::kServerIndex, SIGKILL);
      pending_.push_back({now_wall + kServerPauseWall, [this] { run_.processes().restart(FleetRun::kServerIndex); }});
      return true;
    case monitor::FaultKind::kKillHost:
      return kill_active_host(record, now_wall);
    case monitor::FaultKind::kObstacles: {
      // The server refuses an obstacle over a robot: the next one of the site is tried.
      for (std::size_t k = 0; k < obstacle_ids_.size() && record.target.empty(); ++k) {
        const std::string& id = obstacle_ids_[(static_cast<std::size_t>(fault.target) + k) % obstacle_ids_.size()];
        if (command_server("obstacle", id, "on").empty()) record.target = id;
      }
      if (record.target.empty()) return false;
      pending_.push_back({now_wall + kObstacleOnSim / time_scale_,
                          [this, id = record.target] { command_server("obstacle", id, "off"); }});
      return true;
    }
    case monitor::FaultKind::kMapSwitch: {
      // Every robot onto the next map of the site, round the list.
      const std::string& next_map = site_maps_[(current_map_ + 1) % site_maps_.size()];
      if (!command_server("map", "", next_map).empty()) {
        if (++fault_retries_ <= kMaxMapRetries) {
          retry = true;
        } else {
          log_->warn("fault {}: map-switch to {} given up after {} refusals", faults_.size() + 1, next_map,
                     kMaxMapRetries);
          fault_retries_ = 0;
        }
        return false;
      }
      fault_retries_ = 0;
      current_map_ = (current_map_ + 1) % site_maps_.size();
      record.target = next_map;
      return true;
    }
  }
  return false;
}

bool SoakFaults::kill_active_host(FaultRecord& record, double now_wall) {
  const auto server = run_.servers().find(run_.active_server());
  if (server == run_.servers().end() || !run_.processes().children()[server->second].running) return false;
  const std::size_t index = server->second;
  record.target = server->first;
  run_.expect_exit(index);
  run_.processes().signal(index, SIGKILL);
  pending_.push_back({now_wall + kHostDownWall, [this, index] {
                        // Its host is back: the server starts again as the other's standby.
                        std::vector<std::string> argv = run_.processes().children()[index].argv;
                        if (std::find(argv.begin(), argv.end(), "--standby") == argv.end()) argv.push_back("--standby");
                        run_.processes().restart_with(index, std::move(argv));
                      }});
  return true;
}

bool SoakFaults::inject_agent_fault(const monitor::ScheduledFault& fault, FaultRecord& record, double now_wall) {
  const std::size_t child = index_of_agent(fault.target);
  record.target = run_.robot_ids()[static_cast<std::size_t>(fault.target)];
  if (!run_.processes().children()[child].running) return false;
  record.order = open_order_of(record.target);
  run_.forget_progress(record.target);
  if (fault.kind == monitor::FaultKind::kKillAgent) {
    run_.expect_exit(child);
    run_.processes().signal(child, SIGKILL);
    pending_.push_back({now_wall + kKillPauseWall, [this, child, robot = record.target] {
                          run_.processes().restart(child);
                          run_.forget_progress(robot);
                        }});
  } else {
    run_.processes().signal(child, SIGSTOP);
    pending_.push_back({now_wall + kStallWall, [this, child, robot = record.target] {
                          run_.processes().signal(child, SIGCONT);
                          run_.forget_progress(robot);
                        }});
  }
  return true;
}

void SoakFaults::undo_all() {
  for (auto& p : pending_) p.action();
  pending_.clear();
}

std::string SoakFaults::command_server(const std::string& verb, const std::string& target, const std::string& value) {
  // A refusal is logged and the run goes on.
  model::Command c;
  c.verb = verb;
  c.target = target;
  c.value = value;
  const auto reply = client_.send_command(c, std::chrono::milliseconds(3000));
  if (!reply || !reply->accepted) {
    const std::string error = reply ? reply->error : "no reply from the server";
    log_->warn("{} {} {}: {}", verb, target, value, error);
    return error;
  }
  return std::string();
}

std::int64_t SoakFaults::open_order_of(const std::string& robot) const {
  for (const auto& [id, info] : run_.orders()) {
    if ((info.state == "ASSIGNED" || info.state == "ACTIVE") && info.robot_id == robot) return id;
  }
  return 0;
}

// CPU per process from the first and last samples. Memory growth compares the low-water mark of
// resident memory over the first eighth of the second half with that over the last eighth:
// malloc hands freed memory back to the system in steps, so a single sample swings by several
// percent of a 20 MB process, while a leak raises the low-water mark. A process restarted by a
// fault is compared only once it is past its warm-up (maps, octree and DDS caches filling):
// one restarted within the first eighth of the second half is left out rather than measured
// from its own start. An agent allocates as it first uses a part (a stacker's camera frames at
// its first docking): it is measured once it has finished an order, from its robot's first DONE
// since the process started (a restarted agent allocates afresh).
SoakUsage::SoakUsage(FleetRun& run, double duration_s)
    : run_(run), duration_s_(duration_s), warm_up_s_(std::max(10.0, 0.1 * duration_s)) {
  sample(first_usage_);
  last_usage_ = first_usage_;
}

void SoakUsage::sample(std::map<pid_t, Usage>& into) {
  for (const auto& child : run_.processes().children()) {
    if (!child.running) continue;
    // Fleet's own processes; the broker and the simulated VDA 5050 vehicles are the run's props.
    if (child.name.starts_with("fleet-server")) {
      type_of_[child.pid] = "server";
    } else if (child.name.starts_with("fleet-agent")) {
      type_of_[child.pid] = "agent";
    } else if (child.name.starts_with("fleet-vda5050")) {
      type_of_[child.pid] = "vda5050_bridge";
    } else {
      continue;
    }
    if (const auto space = child.name.find(' '); space != std::string::npos) {
      robot_of_[child.pid] = child.name.substr(space + 1);
    }
    first_seen_s_.emplace(child.pid, run_.wall_seconds());
    if (auto u = usage_of(child.pid)) into[child.pid] = *u;
  }
}

void SoakUsage::step(double elapsed) {
  if (elapsed < next_sample_) return;
  std::map<pid_t, Usage> now_usage;
  sample(now_usage);
  for (const auto& [pid, u] : now_usage) last_usage_[pid] = u;
  next_sample_ += 1.0;
  const double fraction = elapsed / duration_s_;
  if (fraction >= 0.5 && fraction < 0.625) low_water(now_usage, mid_low_kb_);
  if (fraction >= 0.875) low_water(now_usage, end_low_kb_);
}

void SoakUsage::low_water(const std::map<pid_t, Usage>& now_usage, std::map<pid_t, double>& into) {
  for (const auto& [pid, u] : now_usage) {
    if (u.rss_kb <= 0.0 || run_.wall_seconds() - first_seen_s_[pid] < warm_up_s_) continue;
    if (type_of_[pid] == "agent") {
      const std::vector<double>& done = done_s_[robot_of_[pid]];
      const auto first = std::lower_bound(done.begin(), done.end(), first_seen_s_[pid]);
      if (first == done.end() || run_.wall_seconds() - *first < warm_up_s_) continue;
    }
    auto [it, fresh] = into.emplace(pid, u.rss_kb);
    if (!fresh) it->second = std::min(it->second, u.rss_kb);
  }
}

SoakUsage::Figures SoakUsage::figures(double wall, int agents) const {
  // Memory growth over the second half (the worst process of each type, and how many were
  // measured) and CPU over the run, per process type.
  std::map<std::string, double> growth, cpu_s, alive_s;
  std::map<std::string, int> measured;
  for (const auto& [pid, end_kb] : end_low_kb_) {
    const std::string& type = type_of_.at(pid);
    if (auto mid = mid_low_kb_.find(pid); mid != mid_low_kb_.end()) {
      growth[type] =
          std::max(growth.contains(type) ? growth[type] : -100.0, 100.0 * (end_kb - mid->second) / mid->second);
      ++measured[type];
    }
  }
  // CPU: what every process of a type used (a killed one up to its last sample), shared over
  // the type's slots (1 server, N agents) for the whole run: percent of one core per process.
  for (const auto& [pid, type] : type_of_) {
    const auto begin = first_usage_.find(pid);
    const auto end = last_usage_.find(pid);
    const double last_cpu = end != last_usage_.end() ? end->second.cpu_s : 0.0;
    cpu_s[type] += last_cpu - (begin != first_usage_.end() ? begin->second.cpu_s : 0.0);
  }
  alive_s["server"] = wall;
  alive_s["vda5050_bridge"] = wall;
  alive_s["agent"] = wall * agents;
  Figures f;
  for (const auto& [type, g] : growth) f.growth_pct[type] = round_to(g, 0.1);
  for (const auto& [type, n] : measured) f.measured[type] = n;
  for (const auto& [type, c] : cpu_s) f.cpu_pct[type] = round_to(100.0 * c / std::max(1e-9, alive_s[type]), 0.1);
  for (const auto& [type, g] : growth) f.worst_growth = std::max(f.worst_growth, g);
  return f;
}

}  // namespace fleet::cli
