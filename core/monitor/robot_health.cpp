#include "monitor/robot_health.hpp"

namespace fleet::monitor {

std::string_view to_string(RobotHealth health) {
  switch (health) {
    case RobotHealth::kAlive:
      return "alive";
    case RobotHealth::kStale:
      return "stale";
    case RobotHealth::kLost:
      return "lost";
  }
  return "?";
}

bool silent_too_long(double silent_s, double lost_after_s) {
  return silent_s > lost_after_s;
}

RobotHealth robot_health(const HealthFacts& facts) {
  if (facts.lost) return RobotHealth::kLost;
  if (facts.stalled || facts.silent_s > facts.lost_after_s / 2) return RobotHealth::kStale;
  return RobotHealth::kAlive;
}

}  // namespace fleet::monitor
