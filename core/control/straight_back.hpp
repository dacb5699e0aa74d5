#pragma once
// A stacker moving up along its own line: a loader's transporter going on to the next stop in a
// rack aisle, a few metres straight ahead or forks first straight back, where a route and a docking
// would take it round the loop and turn it twice.

#include "geometry/pose.hpp"
#include "sim/tricycle.hpp"

namespace fleet::control {

struct StraightBackParams {
  double max_speed = 0.4;     ///< m/s, backwards (the docking law's fork-in goes at 0.2)
  double acceleration = 0.3;  ///< m/s², speeding up and slowing down
  double lateral_gain = 1.5;  ///< rad of heading towards the line per metre off it, backwards
  /// The same forwards, where the front leads: at most 1 / (rear axle to front) so that the front
  /// corner does not cross the line before the axle comes onto it (a stand beside a rack face).
  double forward_lateral_gain = 0.6;
  double heading_gain = 2.0;  ///< 1/s: yaw rate per rad of heading error
  double tolerance = 0.01;    ///< m: the rear axle this close to the goal along the line is there
  double max_steer = 0.6;     ///< rad: the wheel's largest angle while it drives the line
};

/// Drives the rear axle backwards to `goal` (the rear axle's pose there) along the goal's line:
/// the heading turned towards the line by the lateral error, the speed trapezoidal. The stacker
/// must start on that line facing along it, the goal behind it (straight_behind).
class StraightBack {
 public:
  /// `forward`: the goal lies ahead on the line (straight_ahead), driven to forwards.
  StraightBack(const geometry::Pose2& goal, StraightBackParams params, double wheelbase, bool forward = false);

  /// The wheel command for the rear axle's estimate `rear`; stands once the goal is reached.
  sim::TricycleCommand update(const geometry::Pose2& rear, double dt);
  bool done() const { return done_; }
  /// Metres left along the line from `rear` to the goal, in the direction of travel (negative: past it).
  double left(const geometry::Pose2& rear) const;

 private:
  geometry::Pose2 goal_;
  bool forward_ = false;
  StraightBackParams params_;
  double wheelbase_;
  double speed_ = 0.0;  ///< m/s, the magnitude of the last command
  bool done_ = false;
};

/// Whether a stacker whose rear axle stands at `rear` can reach `goal` (the rear axle's pose
/// there) straight back: on its line within `max_offset` metres, facing the same way within
/// `max_yaw` rad, and between 0.05 m and `max_distance` metres behind it.
bool straight_behind(const geometry::Pose2& rear, const geometry::Pose2& goal, double max_distance,
                     double max_offset = 0.10, double max_yaw = 0.05);
/// The same with the goal ahead of the rear axle on its line.
bool straight_ahead(const geometry::Pose2& rear, const geometry::Pose2& goal, double max_distance,
                    double max_offset = 0.10, double max_yaw = 0.05);
/// The goal lies ahead of the rear axle along the goal's line (StraightBack's `forward`).
bool goal_ahead(const geometry::Pose2& rear, const geometry::Pose2& goal);

}  // namespace fleet::control
