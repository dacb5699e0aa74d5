#include "monitor/fault_plan.hpp"

#include <algorithm>
#include <random>

#include "common/errors.hpp"

namespace fleet::monitor {

namespace {
constexpr FaultKind kAll[] = {FaultKind::kKillAgent, FaultKind::kStallAgent, FaultKind::kKillServer,
                              FaultKind::kObstacles, FaultKind::kMapSwitch};
/// Every kind a list may name: "all" and kill-host, which needs a standby server.
constexpr FaultKind kNamed[] = {FaultKind::kKillAgent, FaultKind::kStallAgent, FaultKind::kKillServer,
                                FaultKind::kObstacles, FaultKind::kMapSwitch,  FaultKind::kKillHost};
}  // namespace

const char* to_string(FaultKind kind) {
  switch (kind) {
    case FaultKind::kKillAgent:
      return "kill-agent";
    case FaultKind::kStallAgent:
      return "stall-agent";
    case FaultKind::kKillServer:
      return "kill-server";
    case FaultKind::kObstacles:
      return "obstacles";
    case FaultKind::kMapSwitch:
      return "map-switch";
    case FaultKind::kKillHost:
      return "kill-host";
  }
  return "?";
}

std::vector<FaultKind> parse_fault_list(const std::string& list) {
  if (list.empty() || list == "none") return {};
  if (list == "all") return {std::begin(kAll), std::end(kAll)};
  std::vector<FaultKind> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = list.substr(start, comma - start);
    const auto* found =
        std::find_if(std::begin(kNamed), std::end(kNamed), [&](FaultKind k) { return name == to_string(k); });
    if (found == std::end(kNamed)) {
      throw InputError("--faults: unknown fault '" + name +
                       "'; choose all, none or a list of kill-agent, stall-agent, kill-server, obstacles, map-switch, "
                       "kill-host");
    }
    if (std::find(out.begin(), out.end(), *found) == out.end()) out.push_back(*found);
    start = comma + 1;
  }
  return out;
}

std::vector<ScheduledFault> plan_faults(const std::vector<FaultKind>& kinds, double duration_sim_s, double period_s,
                                        double quiet_tail_s, int agents, int obstacles, std::uint64_t seed) {
  std::vector<ScheduledFault> plan;
  if (kinds.empty() || period_s <= 0.0 || agents < 1) return plan;
  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 11);
  std::vector<FaultKind> round;
  for (double t = period_s / 2.0; t <= duration_sim_s - quiet_tail_s; t += period_s) {
    if (round.empty()) {
      round = kinds;
      std::shuffle(round.begin(), round.end(), rng);
    }
    const FaultKind kind = round.back();
    round.pop_back();
    int target = 0;
    if (kind == FaultKind::kObstacles) {
      if (obstacles < 1) continue;
      target = std::uniform_int_distribution<int>(0, obstacles - 1)(rng);
    } else {
      target = std::uniform_int_distribution<int>(0, agents - 1)(rng);
    }
    plan.push_back({t, kind, target});
  }
  return plan;
}

std::vector<RobotLoss> unexplained_losses(const std::vector<RobotLoss>& losses,
                                          const std::vector<InjectedFault>& faults, double window_wall) {
  std::vector<RobotLoss> out;
  for (const RobotLoss& loss : losses) {
    const bool explained = std::any_of(faults.begin(), faults.end(), [&](const InjectedFault& f) {
      const bool hits =
          f.kind == FaultKind::kKillServer || f.kind == FaultKind::kKillHost ||
          ((f.kind == FaultKind::kKillAgent || f.kind == FaultKind::kStallAgent) && f.robot_id == loss.robot_id);
      return hits && loss.at_wall >= f.at_wall && loss.at_wall - f.at_wall <= window_wall;
    });
    if (!explained) out.push_back(loss);
  }
  return out;
}

}  // namespace fleet::monitor
