#pragma once

#include <vector>

#include "control/tricycle_pursuit.hpp"
#include "geometry/pose.hpp"
#include "sim/tricycle.hpp"
#include "vehicle/profile.hpp"

namespace fleet::control {

/// A tricycle's body model and its route following, as its vehicle profile gives them.
struct TricycleDrive {
  sim::TricycleParams body;
  TricyclePursuitParams pursuit;
  double control_period = 0.05;  ///< s: the pursuit's rate, 20 Hz

  /// The footprint's centre ahead of the rear-axle midpoint, metres.
  double centre_offset() const { return body.geometry.centre_x(); }
};

/// The body and pursuit of `profile`: its wheelbase, rear axle, steering range, top speed and
/// acceleration over the stacker's defaults [Stacker thesis, section 5.2].
TricycleDrive tricycle_drive_for(const vehicle::VehicleProfile& profile);

/// The rear-axle poses of `ghost` pursuing `path` forwards with nothing in its way, one per
/// `period` seconds of pursuit, until it arrives or has driven `distance`. `ghost` starts as it
/// stands (pose, wheel speed and angle). The stacker sweeps its way ahead with it; traffic
/// reserves what it sweeps through the bends of the roads.
std::vector<geometry::Pose2> roll_forward(sim::Tricycle ghost, const std::vector<geometry::Vec2>& path,
                                          const TricyclePursuitParams& pursuit, double wheelbase, double period,
                                          double distance);

/// The footprint-centre poses of a tricycle driving all of `path` from its first point, heading
/// along its first segment, its rear axle pursuing the path: one per control period. It starts
/// at rest, or `at_speed`: at its top speed along a straight run-up.
std::vector<geometry::Pose2> drive_along(const TricycleDrive& drive, const std::vector<geometry::Vec2>& path,
                                         bool at_speed);

}  // namespace fleet::control
