#pragma once

#include <map>
#include <optional>
#include <string>

#include "model/messages.hpp"

namespace fleet::model {

/// Joins the two halves of what a robot asks of traffic control: its TrafficRequests, which carry
/// the route and go out when it changes (and once a second), and its TrafficProgress samples,
/// which go out at the state rate between them. The two topics arrive in any order: a progress
/// sample applies to the last request of its robot when their version and map match, and a
/// request older than the progress already applied keeps that progress.
class TrafficRequestJoin {
 public:
  /// The request to act on for a new TrafficRequest: `request` itself, or with the later progress
  /// on its route already applied.
  TrafficRequest route(TrafficRequest request);
  /// The request to act on for a progress sample: the robot's last request with this progress, or
  /// nothing when the sample belongs to a route (or map) whose request has not arrived, or is
  /// older than what was applied.
  std::optional<TrafficRequest> progress(const TrafficProgress& progress);
  /// Forgets the robot (gone from the fleet): its next progress waits for a request.
  void forget(const std::string& robot_id) { last_.erase(robot_id); }

 private:
  std::map<std::string, TrafficRequest> last_;  ///< per robot: the last request, progress applied
};

/// Wall seconds between the TrafficRequests of an unchanged route, TrafficProgress going in
/// between: whoever listens longer than this hears every robot's route.
inline constexpr double kRouteRepeatWallS = 1.0;

}  // namespace fleet::model
