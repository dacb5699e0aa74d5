#pragma once
// The parts of `fleetctl soak` (soak_command.cpp): the faults it injects on their schedule, the
// processes' CPU and memory it measures, and the summary it prints.

#include <sys/types.h>

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/client.hpp"
#include "cli/fleet_run.hpp"
#include "cli/processes.hpp"
#include "common/logging.hpp"
#include "monitor/fault_plan.hpp"

namespace fleet::cli {

/// One injected fault and what it led to, in wall seconds from the injection.
struct FaultRecord {
  monitor::FaultKind kind;
  std::string target;
  double at_wall = 0.0;
  double at_sim = 0.0;
  std::int64_t order = 0;  ///< the robot's open order when it happened (agent faults)
  /// Agent faults: the server marked the robot lost. kill-host and kill-server: grants came from
  /// the server that took over or was restarted.
  std::optional<double> detected;
  std::optional<double> recovered;  ///< its order re-queued, failed with a reason, or ended

  /// An agent killed or stopped: the server is to find its robot lost.
  bool on_agent() const { return kind == monitor::FaultKind::kKillAgent || kind == monitor::FaultKind::kStallAgent; }
  /// A fault the fleet is to notice: an agent fault, or the active server's host killed.
  bool to_detect() const { return on_agent() || kind == monitor::FaultKind::kKillHost; }
};

/// A soak's fault schedule carried out against its fleet: agents killed and stopped, the server
/// killed, obstacles switched on and maps switched through the server, each undone after its
/// while; and what each led to (detected, recovered).
class SoakFaults {
 public:
  SoakFaults(FleetRun& run, FleetClient& client, Logger log, std::vector<monitor::ScheduledFault> plan,
             std::vector<std::string> obstacle_ids, std::vector<std::string> site_maps, double time_scale);
  SoakFaults(const SoakFaults&) = delete;
  SoakFaults& operator=(const SoakFaults&) = delete;

  /// The server took `robot` for lost: an agent fault on it is detected.
  void robot_lost(const std::string& robot, double now_wall);
  /// Faults whose robot's order is back in the queue, ended, or running again count as recovered.
  void follow_recovery(const std::map<std::string, bool>& lost, double now_wall);
  /// Undoes what is due (restarts, SIGCONTs, obstacles off), then injects the faults due.
  void step(double now_wall, double elapsed_sim);
  /// Undoes every fault still in force (a stopped agent, a server down).
  void undo_all();
  const std::vector<FaultRecord>& records() const { return faults_; }

  static constexpr double kKillPauseWall = 2.0;  ///< a killed agent stays down this long
  static constexpr double kStallWall = 3.0;      ///< a stopped agent stays frozen this long
  static constexpr double kHostDownWall = 5.0;   ///< a killed server's host comes back after this long

 private:
  /// The fault, carried out; false when it cannot be now (its agent is down, the server refused).
  bool inject(const monitor::ScheduledFault& fault, FaultRecord& record, double now_wall, bool& retry);
  bool inject_agent_fault(const monitor::ScheduledFault& fault, FaultRecord& record, double now_wall);
  /// The active server killed; its host comes back after kHostDownWall with the server as a standby.
  bool kill_active_host(FaultRecord& record, double now_wall);
  /// A command the server carries out (obstacles, maps): its error, "" when it took it.
  std::string command_server(const std::string& verb, const std::string& target, const std::string& value);
  std::int64_t open_order_of(const std::string& robot) const;

  FleetRun& run_;
  FleetClient& client_;
  Logger log_;
  std::vector<monitor::ScheduledFault> plan_;
  std::vector<std::string> obstacle_ids_;
  std::vector<std::string> site_maps_;
  double time_scale_;
  std::vector<FaultRecord> faults_;
  std::size_t next_fault_ = 0;
  double retry_fault_at_wall_ = 0.0;  ///< a refused fault is tried again from then
  int fault_retries_ = 0;
  std::size_t current_map_ = 0;  ///< site_maps_[0] is the site itself
  struct Pending {
    double at_wall;
    std::function<void()> action;
  };
  std::vector<Pending> pending_;
};

/// CPU per process from the first and last samples, and memory growth over the second half of
/// the run per process type.
class SoakUsage {
 public:
  SoakUsage(FleetRun& run, double duration_s);
  /// Every second: samples the processes and keeps the low-water marks of the windows compared.
  void step(double elapsed);
  /// An order done by `robot` (its agent is measured from its first one).
  void order_done(const std::string& robot) { done_s_[robot].push_back(run_.wall_seconds()); }
  /// The last samples, at the end of the run.
  void finish() { sample(last_usage_); }
  struct Figures {
    nlohmann::json growth_pct = nlohmann::json::object();  ///< worst process of each type
    nlohmann::json measured = nlohmann::json::object();    ///< processes measured, per type
    nlohmann::json cpu_pct = nlohmann::json::object();     ///< percent of a core per process
    double worst_growth = 0.0;
  };
  Figures figures(double wall, int agents) const;

 private:
  void sample(std::map<pid_t, Usage>& into);
  void low_water(const std::map<pid_t, Usage>& now_usage, std::map<pid_t, double>& into);

  FleetRun& run_;
  double duration_s_;
  double warm_up_s_;
  double next_sample_ = 1.0;
  std::map<pid_t, Usage> first_usage_, last_usage_;
  std::map<pid_t, double> mid_low_kb_, end_low_kb_;
  std::map<pid_t, std::string> type_of_;
  std::map<pid_t, double> first_seen_s_;  ///< wall seconds into the run
  std::map<pid_t, std::string> robot_of_;
  std::map<std::string, std::vector<double>> done_s_;  ///< wall seconds into the run, by robot
};

/// What a soak run saw besides its FleetRun's own watch.
struct SoakObservations {
  std::string traffic;
  std::map<std::string, std::string> faults_skipped;
  const std::vector<FaultRecord>* faults = nullptr;
  std::vector<monitor::RobotLoss> losses;                 ///< every time the server took a robot for lost
  std::map<std::int64_t, std::set<std::string>> done_by;  ///< order -> robots that reported DONE
  SoakUsage::Figures usage;
  double wall = 0.0;
  std::int64_t refused_samples = 0;  ///< the server's count of robots' messages from the wrong writer
};

/// The soak's summary (what `--json` prints and summary.json keeps), with its "failures".
nlohmann::json soak_summary(const FleetRun& run, const RunOptions& options, const SoakObservations& seen);
/// The summary as text.
void print_soak_summary(std::ostream& out, const FleetRun& run, const nlohmann::json& summary);

}  // namespace fleet::cli
