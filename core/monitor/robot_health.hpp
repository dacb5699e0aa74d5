#pragma once
// The server's verdict on a robot's health from how long it has been silent. The server feeds it
// wall seconds since the robot's last RobotState; DDS tells it of missed deadlines and leases.

#include <string_view>

namespace fleet::monitor {

enum class RobotHealth { kAlive, kStale, kLost };

std::string_view to_string(RobotHealth health);  ///< "alive", "stale", "lost" (the web view's words)

struct HealthFacts {
  bool lost = false;          ///< already counted lost (lease expired, or silent too long)
  bool stalled = false;       ///< missed its RobotState deadline and not heard from since
  double silent_s = 0.0;      ///< wall seconds since its last RobotState
  double lost_after_s = 0.0;  ///< server.robot_lost_after_s
};

/// A robot silent for longer than `lost_after_s` is lost: the server then acts on its order.
bool silent_too_long(double silent_s, double lost_after_s);

/// Lost when counted lost; stale when stalled or silent for over half the time after which it is
/// lost, so the view warns before the server acts; alive otherwise.
RobotHealth robot_health(const HealthFacts& facts);

}  // namespace fleet::monitor
