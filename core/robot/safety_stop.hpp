#pragma once

#include <string>
#include <vector>

#include "control/twist.hpp"
#include "geometry/polygon.hpp"
#include "planning/lidar_sim.hpp"
#include "robot/robot.hpp"

namespace fleet::robot {

struct SafetyStopParams {
  /// The gap kept to every other robot, whatever the task state.
  double safety_gap = 0.03;  ///< metres
  /// A neighbour's pose older than this counts as everywhere it could have reached since.
  double stale_after = 0.5;          ///< sim seconds
  double neighbour_max_speed = 0.3;  ///< m/s, bounds how far a stale neighbour may have moved
  /// Lidar returns within this range feed the stop: the footprint's reach plus what the stop's
  /// 0.4 s horizon can cover at top speed, with room to spare.
  double scan_range = 0.6;      ///< metres
  double escape_within = 0.10;  ///< metres: a refused robot this close to a body steps away
  double escape_speed = 0.03;   ///< m/s of that step
  /// A stop is the same stop while the robot stays within this of where it began.
  double stop_moved = 0.05;  ///< metres
};

/// The last line of defence of every robot type, under traffic and local planning alike: the
/// footprint swept over a command's next moments against the other robots' published poses and
/// the onboard lidar's near returns. Also keeps the books on who the robot stopped for, so a
/// lasting stop reaches the traffic manager (TrafficRoute::stopped_for).
class SafetyStop {
 public:
  SafetyStop(SafetyStopParams params, geometry::Footprint footprint) : params_(params), footprint_(footprint) {}

  /// The returns of a scan near the robot, placed with the pose estimate the scan was taken at:
  /// read relative to the estimate later, so a bias of the estimate cancels.
  void take_scan(const planning::LidarScan& scan);
  /// Near returns in map coordinates, as take_scan() keeps them.
  void set_returns(std::vector<geometry::Vec2> returns) { returns_ = std::move(returns); }

  /// `cmd`, or a stop when it would bring the footprint at `estimate` within safety_gap of
  /// another robot and closer than it is now; close beside a body, a slow step straight away
  /// from it when that step is itself safe (an omnidirectional base makes room to turn).
  control::BodyTwist safe(const control::BodyTwist& cmd, const geometry::Pose2& estimate,
                          const std::vector<Neighbour>& neighbours) const;
  /// Whether `cmd` would bring the footprint within `safety_gap` of another robot (see safe()).
  bool moves_too_close(const control::BodyTwist& cmd, const geometry::Pose2& estimate,
                       const std::vector<Neighbour>& neighbours) const;

  /// The neighbour whose footprint is nearest the one at `pose` and within `within` metres of
  /// it; empty when none is.
  std::string robot_within(const geometry::Pose2& pose, const std::vector<Neighbour>& neighbours, double within) const;

  /// The robot stands stopped for `robot_id`'s body at sim time `t` at `here` (nothing when the
  /// id is empty). A stop is kept through its flicker (the check clears for a step as poses
  /// arrive, then stops again) while this robot has not moved away.
  void note(double t, geometry::Vec2 here, const std::string& robot_id);
  /// A new route: a stop is reported for the route it happened on, after lasting on it.
  void clear() { stop_ = {}; }
  /// Who the robot at `here` has stood stopped for since long enough to tell the traffic manager
  /// (kReportStopAfter) at sim time `t`: one id or none.
  std::vector<std::string> stopped_for(double t, geometry::Vec2 here) const;

  const geometry::Footprint& footprint() const { return footprint_; }

 private:
  struct Stop {
    std::string robot_id;
    double since = 0.0;
    geometry::Vec2 where;
    double last_seen = -1.0;
    /// Still the same stop at time `t` with this robot at `here`: seen lately, not moved away.
    bool current(double t, geometry::Vec2 here, double moved) const;
  };

  SafetyStopParams params_;
  geometry::Footprint footprint_;
  std::vector<geometry::Vec2> returns_;
  Stop stop_;
};

}  // namespace fleet::robot
