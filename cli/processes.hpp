#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "app/process.hpp"

namespace fleet::cli {

/// Child processes started by fleetctl (demo, soak). Each child is told by the kernel to die
/// with fleetctl (PR_SET_PDEATHSIG), so none outlives it, even when fleetctl is killed with
/// SIGKILL; stop_all() ends them cleanly first (SIGTERM, then SIGKILL after a grace period).
class ProcessGroup {
 public:
  struct Child {
    std::string name;
    std::vector<std::string> argv;
    std::string log_file;
    pid_t pid = -1;
    bool running = false;
    int exit_status = 0;  ///< as from waitpid, once ended
  };

  ProcessGroup() = default;
  ~ProcessGroup();
  ProcessGroup(const ProcessGroup&) = delete;
  ProcessGroup& operator=(const ProcessGroup&) = delete;

  /// Starts `argv` with stdout and stderr appended to `log_file`. Returns the child's index.
  std::size_t start(const std::string& name, const std::vector<std::string>& argv, const std::string& log_file);

  /// Restarts an ended child with its original arguments.
  void restart(std::size_t index);
  /// Restarts an ended child with `argv`, which it keeps for later restarts.
  void restart_with(std::size_t index, std::vector<std::string> argv);

  /// Sends `signal` to one child.
  void signal(std::size_t index, int signal);

  /// Reaps ended children; returns the indices that ended since the last call.
  std::vector<std::size_t> reap();

  /// SIGTERM to every running child, then SIGKILL to those still running after `grace_s`.
  void stop_all(double grace_s = 5.0);

  const std::vector<Child>& children() const { return children_; }

  /// "exited with 0", "killed by signal 9", ...
  static std::string describe(int exit_status);

 private:
  std::vector<Child> children_;
};

/// Resident memory (kB) and CPU time (s) of a process, from /proc.
struct Usage {
  double rss_kb = 0.0;
  double peak_rss_kb = 0.0;  ///< VmHWM: the most it was resident
  double cpu_s = 0.0;
};
/// Nothing once the process is gone.
std::optional<Usage> usage_of(pid_t pid);

/// Bytes received on the loopback interface since boot (/proc/net/dev); on loopback every byte
/// sent is received once. Nothing when it cannot be read.
std::optional<double> loopback_bytes();

/// SIGINT and SIGTERM set a flag instead of killing fleetctl, so it can stop its children and
/// print its summary: the daemons' handlers (app/process.hpp).
using app::install_stop_handlers;
using app::stop_requested;

}  // namespace fleet::cli
