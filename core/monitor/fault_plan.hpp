#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fleet::monitor {

/// The faults a soak run can inject.
/// kKillHost kills the active one of two servers (a soak with a standby), as its host dying would.
enum class FaultKind { kKillAgent, kStallAgent, kKillServer, kObstacles, kMapSwitch, kKillHost };

const char* to_string(FaultKind kind);
/// The kinds named by a `--faults` list: "none", "all" (every kind but kill-host), or
/// comma-separated names (kill-agent, stall-agent, kill-server, obstacles, map-switch, kill-host).
/// InputError naming the unknown one otherwise.
std::vector<FaultKind> parse_fault_list(const std::string& list);

struct ScheduledFault {
  double at_sim = 0.0;  ///< sim seconds after the run's start
  FaultKind kind = FaultKind::kKillAgent;
  int target = 0;  ///< agent index (0-based) for agent faults, obstacle index for obstacles
};

/// A reproducible fault schedule: one fault every `period_s` sim seconds from `period_s / 2`,
/// the kinds in a seeded random order that uses each kind once per round, targets drawn from
/// the seed. Nothing in the last `quiet_tail_s` sim seconds, so the run ends recovered.
std::vector<ScheduledFault> plan_faults(const std::vector<FaultKind>& kinds, double duration_sim_s, double period_s,
                                        double quiet_tail_s, int agents, int obstacles, std::uint64_t seed);

/// A fault as it was injected: its kind, the robot it hit (agent faults) and when, wall seconds.
struct InjectedFault {
  FaultKind kind = FaultKind::kKillAgent;
  std::string robot_id;  ///< agent faults only
  double at_wall = 0.0;
};

/// A robot the server took for lost, and when (wall and sim seconds of the run).
struct RobotLoss {
  std::string robot_id;
  double at_wall = 0.0;
  double at_sim = 0.0;
};

/// The losses no injected fault accounts for: a robot is expected lost within `window_wall`
/// seconds after its own agent was killed or stopped, and any robot after the server was killed.
/// Any other loss means a process that stood still or a link that broke with nothing injected.
std::vector<RobotLoss> unexplained_losses(const std::vector<RobotLoss>& losses,
                                          const std::vector<InjectedFault>& faults, double window_wall);

}  // namespace fleet::monitor
