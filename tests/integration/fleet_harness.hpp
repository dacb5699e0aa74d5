#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli/processes.hpp"
#include "test_paths.hpp"

namespace fleet::testing {

/// The output and exit code of a finished command.
struct CommandResult {
  int exit_code = -1;
  std::string out;  ///< stdout
  std::string err;  ///< stderr
};

/// The last line of a command's output as JSON (what `--json` ends with).
nlohmann::json last_json_line(const std::string& text);

class FleetHarness;
/// Polls `fleetctl order list` until `done` holds for its rows or `timeout_s` (wall) passes; the
/// rows last read.
nlohmann::json orders_until(FleetHarness& fleet, const std::function<bool(const nlohmann::json&)>& done,
                            double timeout_s);

/// Runs a command to its end (with a wall-clock limit), capturing stdout and stderr.
CommandResult run_command(const std::vector<std::string>& argv, double timeout_s = 120.0);

/// A fleet of real processes for one test on its own DDS domain. Every process it started is
/// stopped when it goes out of scope, also when the test fails.
class FleetHarness {
 public:
  FleetHarness(int domain, double time_scale, std::string site = "table_a");
  ~FleetHarness();

  /// The configuration file every process of the harness reads (default: config/fleet.yaml).
  void use_config(std::string path) { config_path_ = std::move(path); }
  void start_server(const std::vector<std::string>& extra = {});
  void start_agent(const std::string& robot_id, const std::vector<std::string>& extra = {});

  /// Waits until every robot in `robot_ids` publishes RobotState (so it is registered and free).
  bool wait_for_robots(const std::vector<std::string>& robot_ids, double timeout_s = 30.0) const;

  /// fleetctl with --domain set.
  CommandResult fleetctl(std::vector<std::string> args, double timeout_s = 120.0) const;

  std::string log_of(const std::string& name) const;
  cli::ProcessGroup& processes() { return processes_; }
  int domain() const { return domain_; }
  const std::string& log_dir() const { return log_dir_; }
  const std::string& config_path() const { return config_path_; }
  /// The flags every process of the harness takes: --config, --domain, --site, --time-scale.
  std::vector<std::string> common_args() const;

 private:
  std::string config_path_ = fleet::test::source_dir() + "/config/fleet.yaml";
  int domain_;
  double time_scale_;
  std::string site_;
  std::string log_dir_;
  cli::ProcessGroup processes_;
};

std::string bin(const std::string& name);

/// Order ids the agents of `robots` logged as done (pallet placed), with how often.
std::map<std::int64_t, int> done_counts(const FleetHarness& fleet, const std::vector<std::string>& robots);

}  // namespace fleet::testing
