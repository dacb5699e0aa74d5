#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "cli/processes.hpp"
#include "cli/vda5050_vehicles.hpp"
#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "dds/topics.hpp"
#include "map/site.hpp"
#include "monitor/aisle_share.hpp"
#include "monitor/collision_monitor.hpp"
#include "monitor/localization_watch.hpp"
#include "monitor/order_accounting.hpp"
#include "monitor/progress_monitor.hpp"
#include "monitor/track_recorder.hpp"

namespace fleet::cli {

/// 128 random bits as hex: a web view's API token for a fleet fleetctl starts (demo, load).
std::string random_token();

/// The most agent processes `fleetctl demo` and `fleetctl soak` start on one host.
constexpr int kMaxAgents = 256;

struct RunOptions {
  std::string kind = "demo";  ///< names the run folder: <state folder>/runs/<kind>-<time>
  int agents = 4;
  std::string site;
  double duration_s = 0.0;  ///< wall seconds; 0 runs until Ctrl-C
  double time_scale = 1.0;
  long seed = 1;
  std::uint32_t domain = 0;
  std::string config_file;
  bool auto_orders = true;
  int http_port = 8080;   ///< the server's web view; 0 turns it off
  std::string api_token;  ///< for the web view's controls
  std::vector<std::string> extra_server_args;
  std::vector<std::string> extra_agent_args;
  /// Words put before each agent's command line, "{n}" replaced by the agent's number (1..N):
  /// e.g. "ip netns exec fleet-agent{n}" runs each agent in its own network namespace.
  std::string agent_wrap;
  /// Simulated VDA 5050 vehicles of the configuration's fleets of robot type vda5050, with a
  /// broker and fleet-vda5050 (cli/vda5050_vehicles.hpp); 0: none.
  int vda5050_vehicles = 0;
  /// A second server, `fleet-server --standby` on a database of its own, started after the agents
  /// (the servers are server-1 and server-2).
  bool standby = false;
  /// Words put before the standby server's command line (its own host: "ip netns exec ...").
  std::string standby_wrap;
  /// Every robot's true and estimated track of the whole run, written to tracks.csv in the run
  /// directory at its end (`fleetctl map render --tracks`); else only the last 90 s beside a report.
  bool whole_tracks = false;
};

/// How late one agent's control steps run against the clock (model::RobotState's control_lag).
struct ControlLag {
  std::string robot;
  double p50_s = 0.0;
  double p99_s = 0.0;
  double period_s = 0.0;
  std::int64_t steps_skipped = 0;
};

/// A whole Fleet on this host: one fleet-server and N fleet-agents as child processes on one DDS
/// domain, watched by fleetctl (orders, ground-truth collisions, crashed processes).
class FleetRun {
 public:
  FleetRun(RunOptions options, config::FleetConfig config, Logger log);
  ~FleetRun();

  /// Starts the server, then the agents one after another (each once the one before publishes its
  /// state, or after kAgentStartWait), and waits for the server to answer; throws with the log of
  /// a process that ended meanwhile.
  void start();
  /// Reads what the fleet publishes; call often. Returns false once the run should end.
  bool poll();
  /// Stops every child (clean SIGTERM first) after reading the final order states.
  void stop();

  double sim_seconds() const;
  double wall_seconds() const;
  monitor::OrderTally tally() const;
  const std::vector<monitor::Collision>& collisions() const { return collisions_.collisions(); }
  /// Robots with an order that made no progress for 60 sim seconds, 180 queued behind robots that
  /// move (see ProgressMonitor).
  const monitor::ProgressMonitor& progress() const { return progress_; }
  const std::map<std::int64_t, model::OrderInfo>& orders() const { return orders_; }
  /// Each fleet's localization error: estimates (RobotState) against the simulation's truth.
  std::map<std::string, monitor::ErrorFigures> localization_by_fleet() const;
  /// The fleet of a robot of the run, empty for one the configuration does not know.
  std::string fleet_of(const std::string& robot_id) const;
  const monitor::LocalizationWatch& localization() const { return localization_; }
  /// The agent whose control steps run latest at p99 (its last report), with its period;
  /// none before any agent reported.
  std::optional<ControlLag> worst_control_lag() const;
  /// Each fleet's worst p99 lateness of control steps, simulated seconds (fleets with a report).
  std::map<std::string, double> control_lag_p99_by_fleet() const;
  /// Two or more pickers in one rack aisle; none without two pickers or racks.
  const monitor::AisleShareWatch* aisle_share() const { return aisle_share_ ? &*aisle_share_ : nullptr; }
  /// Orders done in the run per fleet of the robot that did them, every fleet of the
  /// configuration listed (0 when none).
  std::map<std::string, long> done_by_fleet() const;
  /// The robot was frozen or down by an injected fault: its progress watch starts again, so the
  /// time it was gone does not count as time without progress.
  void forget_progress(const std::string& robot_id) { progress_.forget(robot_id); }
  /// An injected fault will end this child: its end is not a crash.
  void expect_exit(std::size_t child_index) { expected_exits_.insert(child_index); }
  /// Index of the server (0) and of each agent (1..N) in processes().
  static constexpr std::size_t kServerIndex = 0;
  /// With a standby: the index in processes() of each server by id (server-1, server-2).
  const std::map<std::string, std::size_t>& servers() const { return servers_; }
  /// The server heard last serving as active (its ServerLoad), empty before one was heard.
  const std::string& active_server() const { return active_server_; }
  /// The first wall time (wall_now) after `since` at which a grant came from a DDS writer not heard
  /// before `since`: grants flowing from a server that took over.
  std::optional<double> grants_from_a_new_writer_since(double since) const;
  /// Sim time (shared clock) when the run started.
  double start_sim() const { return start_sim_; }
  /// Children that ended on their own (not stopped by us), with how they ended.
  const std::vector<std::string>& crashes() const { return crashes_; }
  const std::string& run_dir() const { return run_dir_; }
  ProcessGroup& processes() { return processes_; }
  /// The robots driven by fleet-agent processes.
  const std::vector<std::string>& robot_ids() const { return robot_ids_; }
  /// The simulated VDA 5050 vehicles, empty without --vda5050-vehicles.
  const std::vector<std::string>& vda5050_robot_ids() const { return vda5050_.robot_ids; }

 private:
  static constexpr std::chrono::seconds kAgentStartWait{10};
  /// Throws when a started process has ended, with the end of its log.
  void throw_if_a_process_ended();
  /// fleet-server's command line with the run's `common` arguments, on database `db`, its web
  /// view on `http_port` (0: off).
  std::vector<std::string> server_command(const std::vector<std::string>& common, const std::string& db,
                                          int http_port) const;
  /// Starts fleet-server --standby (server-2) with the run's `common` arguments.
  void start_standby(const std::vector<std::string>& common);
  std::string binary(const std::string& name) const;
  /// With two pickers or more and racks on the site: the aisles between the racks to watch.
  void watch_pickers_in_aisles(const map::Site& site);
  /// Logs each robot whose estimate went far from the truth, with the tracks of both.
  void report_far_off_estimates();
  /// Writes every robot's track of the last `seconds` sim into the run folder as `name`.csv.
  void write_tracks(const std::string& name, double seconds, double now_sim);

  RunOptions options_;
  config::FleetConfig config_;
  Logger log_;
  std::string run_dir_;
  std::vector<std::string> robot_ids_;
  Vda5050Vehicles vda5050_;
  ProcessGroup processes_;
  std::chrono::steady_clock::time_point started_;
  std::chrono::steady_clock::time_point ended_;
  double start_sim_ = 0.0;
  bool stopped_ = false;
  std::unique_ptr<dds::Participant> participant_;
  std::unique_ptr<dds::Reader<model::OrderInfo>> order_reader_;
  std::unique_ptr<dds::Reader<model::SimTruth>> truth_reader_;
  std::unique_ptr<dds::Reader<model::RobotState>> state_reader_;
  std::unique_ptr<dds::Reader<model::TrafficGrant>> grant_reader_;
  std::unique_ptr<dds::Reader<model::ServerLoad>> server_load_reader_;
  std::map<std::string, std::size_t> servers_;
  std::string active_server_;
  /// Each DDS writer of grants by the wall time its first grant came (wall_now).
  std::map<dds_instance_handle_t, double> grant_writers_;
  monitor::ProgressMonitor progress_;
  std::map<std::string, std::string> task_of_;  ///< robot -> its open order and phase
  std::set<std::string> works_standing_;        ///< robots standing by design (ProgressMonitor::update)
  std::map<std::int64_t, model::OrderInfo> orders_;
  monitor::CollisionMonitor collisions_;
  monitor::LocalizationWatch localization_;
  int estimates_far_off_ = 0;
  std::map<std::string, ControlLag> control_lag_;  ///< each robot's last report
  std::optional<monitor::AisleShareWatch> aisle_share_;
  monitor::TrackRecorder tracks_;
  std::vector<std::string> crashes_;
  std::set<std::size_t> expected_exits_;
};

/// {robot, p50_s, p99_s, period_s, steps_skipped}, or {} before any agent reported, for the summaries.
nlohmann::json control_lag_json(const std::optional<ControlLag>& lag);

/// `v` to a multiple of `step` (0.1, 0.01, ...), printed without binary noise (170.6, not 170.60000000000002).
double round_to(double v, double step);

/// "forklifts 12, reach_trucks 9", for the summaries.
std::string fleet_counts(const std::map<std::string, long>& counts);

/// `fleetctl soak` (soak_command.cpp).
int soak_command(const struct CommandArgs& args, std::ostream& out, std::ostream& err, std::uint32_t domain);
/// `fleetctl load`: a real fleet-server against N emulated robots (cli/emulated_fleet.hpp), with
/// what the server's work costs.
int load_command(const struct CommandArgs& args, std::ostream& out, std::ostream& err, std::uint32_t domain);

/// `fleetctl demo`.
int demo_command(const struct CommandArgs& args, std::ostream& out, std::ostream& err, std::uint32_t domain);

}  // namespace fleet::cli
