#pragma once

#include <vector>

#include "geometry/pose.hpp"
#include "sim/tricycle.hpp"

namespace fleet::control {

/// Settings of the stacker's route following. The thesis drives its corridor by the attractor
/// dynamics towards one target at a time [Stacker thesis, Ch. 3, 6.1]; on the plant's roads the
/// route is a polyline granted piece by piece by the traffic manager, and pure pursuit of the rear
/// axle along it keeps the stacker on its lane's centre line (keeping right, Stacker thesis, Fig. 5.5).
struct TricyclePursuitParams {
  double max_speed = 1.2;             ///< m/s of the rear axle
  double acceleration = 0.5;          ///< for braking towards the end of the path or the grant, m/s^2
  double lateral_acceleration = 0.4;  ///< speed in a bend: v^2 |curvature| <= this, m/s^2
  double lookahead = 1.0;             ///< along the path from the rear axle's projection, m
  double arrive_tolerance = 0.15;     ///< the path's end is reached within this, m
  double pivot_above = 1.4;           ///< |bearing| of the lookahead point beyond which it pivots first, rad
  double pivot_yaw_rate = 0.4;        ///< rad/s while pivoting
  double creep_speed = 0.05;          ///< m/s: the least speed while room is left
  /// The rear axle stops this far short of the path's end, m: with the body's centre this far
  /// ahead of it, the centre stands on the end (where traffic placed the robot).
  double stop_short = 0.0;
};

struct TricyclePursuitOutput {
  sim::TricycleCommand command;
  double remaining = 0.0;  ///< path length left from the rear axle's projection, m
  bool arrived = false;
};

/// Pure pursuit of the rear-axle midpoint (`rear`) along `path`, forwards. `room` caps the distance
/// it may drive (the traffic grant, an obstacle ahead). `steer_angle` is the measured wheel angle:
/// the wheel does not roll until it has turned near the angle asked for.
TricyclePursuitOutput pursue(const geometry::Pose2& rear, const std::vector<geometry::Vec2>& path, double room,
                             double steer_angle, const TricyclePursuitParams& params, double wheelbase);

}  // namespace fleet::control
