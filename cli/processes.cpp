#include "cli/processes.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace fleet::cli {

ProcessGroup::~ProcessGroup() {
  stop_all(2.0);
}

std::size_t ProcessGroup::start(const std::string& name, const std::vector<std::string>& argv,
                                const std::string& log_file) {
  children_.push_back({name, argv, log_file, -1, false, 0});
  restart(children_.size() - 1);
  return children_.size() - 1;
}

void ProcessGroup::restart_with(std::size_t index, std::vector<std::string> argv) {
  children_.at(index).argv = std::move(argv);
  restart(index);
}

void ProcessGroup::restart(std::size_t index) {
  Child& child = children_.at(index);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("cannot start " + child.name + ": " + std::strerror(errno));
  if (pid == 0) {
    // In the child: die with the parent, stay out of the terminal's process group (so Ctrl-C
    // reaches fleetctl alone and it stops the children in order), log to the file.
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);
    setpgid(0, 0);
    const int fd = open(child.log_file.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
      close(fd);
    }
    std::vector<char*> args;
    for (const auto& a : child.argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());  // a wrapper such as "ip" is found on PATH
    std::fprintf(stderr, "cannot execute %s: %s\n", args[0], std::strerror(errno));
    _exit(127);
  }
  setpgid(pid, pid);  // also here, so the group exists before the first signal to it
  child.pid = pid;
  child.running = true;
  child.exit_status = 0;
}

void ProcessGroup::signal(std::size_t index, int sig) {
  Child& child = children_.at(index);
  // The whole group: a wrapper (heaptrack, a shell) may have forked the real process.
  if (child.running) kill(-child.pid, sig);
}

std::vector<std::size_t> ProcessGroup::reap() {
  std::vector<std::size_t> ended;
  for (std::size_t i = 0; i < children_.size(); ++i) {
    Child& child = children_[i];
    if (!child.running) continue;
    int status = 0;
    if (waitpid(child.pid, &status, WNOHANG) == child.pid) {
      child.running = false;
      child.exit_status = status;
      ended.push_back(i);
    }
  }
  return ended;
}

void ProcessGroup::stop_all(double grace_s) {
  for (auto& child : children_) {
    if (child.running) {
      kill(-child.pid, SIGCONT);  // a stopped child cannot act on SIGTERM
      kill(-child.pid, SIGTERM);
    }
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_s);
  for (;;) {
    reap();
    bool any = false;
    for (const auto& child : children_) any = any || child.running;
    if (!any) return;
    if (std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  for (auto& child : children_) {
    if (!child.running) continue;
    kill(-child.pid, SIGKILL);
    int status = 0;
    waitpid(child.pid, &status, 0);
    child.running = false;
    child.exit_status = status;
  }
  // What a wrapper left behind in a group after the wrapper itself ended.
  for (const auto& child : children_) {
    if (child.pid > 0) kill(-child.pid, SIGKILL);
  }
}

std::string ProcessGroup::describe(int exit_status) {
  if (WIFEXITED(exit_status)) return "exited with " + std::to_string(WEXITSTATUS(exit_status));
  if (WIFSIGNALED(exit_status)) return "killed by signal " + std::to_string(WTERMSIG(exit_status));
  return "ended (status " + std::to_string(exit_status) + ")";
}

std::optional<Usage> usage_of(pid_t pid) {
  Usage u;
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  if (!status) return std::nullopt;
  for (std::string line; std::getline(status, line);) {
    if (line.starts_with("VmRSS:")) u.rss_kb = std::stod(line.substr(6));
    if (line.starts_with("VmHWM:")) u.peak_rss_kb = std::stod(line.substr(6));
  }
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  // Fields after the command name (which may hold spaces) start after the last ')'.
  const auto close = text.rfind(')');
  if (close == std::string::npos || close + 2 > text.size()) return std::nullopt;
  std::istringstream rest(text.substr(close + 2));
  std::vector<std::string> fields;
  for (std::string f; rest >> f;) fields.push_back(f);
  if (fields.size() < 13) return std::nullopt;
  u.cpu_s = (std::stod(fields[11]) + std::stod(fields[12])) / static_cast<double>(sysconf(_SC_CLK_TCK));
  return u;
}

std::optional<double> loopback_bytes() {
  std::ifstream dev("/proc/net/dev");
  for (std::string line; std::getline(dev, line);) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream name(line.substr(0, colon));
    std::string interface;
    name >> interface;
    if (interface != "lo") continue;
    std::istringstream counters(line.substr(colon + 1));
    double received = 0.0;
    if (counters >> received) return received;
  }
  return std::nullopt;
}

}  // namespace fleet::cli
