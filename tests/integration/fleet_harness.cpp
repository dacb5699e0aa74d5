#include "fleet_harness.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <set>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "dds/environment.hpp"
#include "test_paths.hpp"

namespace fleet::testing {

std::string bin(const std::string& name) {
  return fleet::test::bin_dir() + "/" + name;
}

namespace {
std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

CommandResult run_command(const std::vector<std::string>& argv, double timeout_s) {
  const std::string dir = std::filesystem::temp_directory_path() / ("fleet-cmd-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  static int counter = 0;
  const std::string out_file = dir + "/out" + std::to_string(++counter);
  const std::string err_file = dir + "/err" + std::to_string(counter);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    const int out = open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(out, STDOUT_FILENO);
    dup2(err, STDERR_FILENO);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  CommandResult result;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) != pid) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      result.exit_code = -1;
      result.out = slurp(out_file);
      result.err = slurp(err_file) + "\n[killed after " + std::to_string(timeout_s) + " s]";
      return result;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  result.out = slurp(out_file);
  result.err = slurp(err_file);
  // What the command printed is in the result now; thousands of runs left their files in /tmp.
  std::error_code ignored;
  std::filesystem::remove(out_file, ignored);
  std::filesystem::remove(err_file, ignored);
  std::filesystem::remove(dir, ignored);  // only when empty
  return result;
}

FleetHarness::FleetHarness(int domain, double time_scale, std::string site)
    : domain_(domain), time_scale_(time_scale), site_(std::move(site)) {
  dds::use_fleet_dds_config();  // the test process may be a DDS participant too
  log_dir_ = std::filesystem::temp_directory_path() /
             ("fleet-test-" + std::to_string(getpid()) + "-" + std::to_string(domain));
  std::filesystem::remove_all(log_dir_);
  std::filesystem::create_directories(log_dir_);
}

FleetHarness::~FleetHarness() {
  processes_.stop_all(5.0);
  // The processes' logs are kept for a failed test (its messages name them), dropped otherwise.
  if (::testing::Test::HasFailure()) {
    std::cerr << "logs of this fleet: " << log_dir_ << "/\n";
  } else {
    std::error_code ignored;
    std::filesystem::remove_all(log_dir_, ignored);
  }
}

nlohmann::json last_json_line(const std::string& text) {
  const auto end = text.find_last_not_of('\n');
  const auto start = text.rfind('\n', end);
  const std::size_t from = start == std::string::npos ? 0 : start + 1;
  return nlohmann::json::parse(text.substr(from, end - from + 1));
}

nlohmann::json orders_until(FleetHarness& fleet, const std::function<bool(const nlohmann::json&)>& done,
                            double timeout_s) {
  nlohmann::json rows;
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    const auto list = fleet.fleetctl({"--json", "order", "list"}, 30);
    if (list.exit_code == 0) {
      rows = last_json_line(list.out);
      if (done(rows)) return rows;
    }
    std::this_thread::sleep_for(std::chrono::seconds(2));
  }
  return rows;
}

std::vector<std::string> FleetHarness::common_args() const {
  return {"--config", config_path_, "--domain",     std::to_string(domain_),
          "--site",   site_,        "--time-scale", std::to_string(time_scale_)};
}

void FleetHarness::start_server(const std::vector<std::string>& extra) {
  std::vector<std::string> argv{bin("fleet-server"), "--db", log_dir_ + "/fleet.db"};
  for (const auto& a : common_args()) argv.push_back(a);
  argv.insert(argv.end(), extra.begin(), extra.end());
  // No web view unless the test asks for one, so test servers never take a running demo's port.
  if (std::find(extra.begin(), extra.end(), "--http-port") == extra.end()) {
    argv.insert(argv.end(), {"--http-port", "0"});
  }
  processes_.start("fleet-server", argv, log_dir_ + "/fleet-server.log");
}

void FleetHarness::start_agent(const std::string& robot_id, const std::vector<std::string>& extra) {
  std::vector<std::string> argv{bin("fleet-agent"), "--id", robot_id};
  for (const auto& a : common_args()) argv.push_back(a);
  argv.insert(argv.end(), extra.begin(), extra.end());
  processes_.start("fleet-agent " + robot_id, argv, log_dir_ + "/fleet-agent-" + robot_id + ".log");
}

CommandResult FleetHarness::fleetctl(std::vector<std::string> args, double timeout_s) const {
  std::vector<std::string> argv{bin("fleetctl"), "--domain", std::to_string(domain_), "--config", config_path_};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_command(argv, timeout_s);
}

bool FleetHarness::wait_for_robots(const std::vector<std::string>& robot_ids, double timeout_s) const {
  cli::FleetClient client(static_cast<std::uint32_t>(domain_));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  std::set<std::string> seen;
  while (std::chrono::steady_clock::now() < deadline) {
    for (const auto& [id, state] : client.robot_states(std::chrono::milliseconds(200))) seen.insert(id);
    if (std::all_of(robot_ids.begin(), robot_ids.end(), [&](const std::string& id) { return seen.contains(id); })) {
      return true;
    }
  }
  return false;
}

std::string FleetHarness::log_of(const std::string& name) const {
  return slurp(log_dir_ + "/" + name + ".log");
}

/// Order ids each agent logged as done, with how often.
std::map<std::int64_t, int> done_counts(const FleetHarness& fleet, const std::vector<std::string>& robots) {
  std::map<std::int64_t, int> counts;
  const std::regex done(R"(order (\d+) done: )");
  for (const auto& robot : robots) {
    const std::string log = fleet.log_of("fleet-agent-" + robot);
    for (std::sregex_iterator it(log.begin(), log.end(), done), end; it != end; ++it) ++counts[std::stoll((*it)[1])];
  }
  return counts;
}

}  // namespace fleet::testing
