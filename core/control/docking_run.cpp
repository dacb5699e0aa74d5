#include "control/docking_run.hpp"

#include <cmath>
#include <limits>
#include <memory>
#include <random>

namespace fleet::control {

namespace {

geometry::Vec2 row_direction(const geometry::Pose2& pallet) {
  return {-std::sin(pallet.yaw), std::cos(pallet.yaw)};
}

/// A pose of the true map frame seen from the estimated one: the same pose relative to the
/// vehicle. A camera measures the pallet relative to the vehicle; the map frame it is put in is the
/// vehicle's estimate.
geometry::Pose2 reframe(const geometry::Pose2& from_vehicle, const geometry::Pose2& to_vehicle,
                        const geometry::Pose2& pose) {
  return geometry::body_pose_to_map(to_vehicle, geometry::map_pose_to_body(from_vehicle, pose));
}

/// What the pose sensor reads for a vehicle at `truth`.
geometry::Pose2 pose_sensor_reading(const geometry::Pose2& truth, const PoseSensorNoise& noise, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  return {truth.x + noise.position_sigma * unit(rng), truth.y + noise.position_sigma * unit(rng),
          geometry::normalize_angle(truth.yaw + noise.yaw_sigma * unit(rng))};
}

/// Moves `estimate` by the motion from `before` to `after` (in the vehicle frame), with the
/// odometry's error.
geometry::Pose2 odometry_step(const geometry::Pose2& estimate, const geometry::Pose2& before,
                              const geometry::Pose2& after, const OdometryNoise& noise, std::mt19937_64& rng) {
  geometry::Pose2 seen = geometry::map_pose_to_body(before, after);
  const double length = std::hypot(seen.x, seen.y);
  std::normal_distribution<double> unit(0.0, 1.0);
  seen.x += noise.distance_fraction * length * unit(rng);
  seen.y += noise.distance_fraction * length * unit(rng);
  seen.yaw += noise.yaw_per_metre * length * unit(rng);
  return geometry::body_pose_to_map(estimate, seen);
}

}  // namespace

PalletDetector make_simulated_detector(const geometry::Pose2& pallet, const SimulatedDetectorParams& params,
                                       std::uint64_t seed) {
  std::vector<geometry::Pose2> row;
  const geometry::Vec2 along = row_direction(pallet);
  const int n = params.neighbour_pitch > 0.0 ? params.neighbours_each_side : 0;
  for (int k = -n; k <= n; ++k) {
    const geometry::Vec2 c = pallet.position() + (k * params.neighbour_pitch) * along;
    row.push_back({c.x, c.y, pallet.yaw});
  }
  auto rng = std::make_shared<std::mt19937_64>(seed);
  return [row, params, rng](const geometry::Pose2& vehicle, const geometry::Pose2& expected,
                            double) -> std::optional<geometry::Pose2> {
    const geometry::Pose2* best = nullptr;
    double best_distance = std::numeric_limits<double>::infinity();
    for (const geometry::Pose2& p : row) {
      const geometry::Vec2 face =
          p.position() + (0.5 * params.pallet_depth) * geometry::Vec2{std::cos(p.yaw), std::sin(p.yaw)};
      const double range = geometry::distance(face, vehicle.position());
      if (range < params.min_range || range > params.max_range) continue;
      const double d = geometry::distance(p.position(), expected.position());
      if (d < best_distance) {
        best_distance = d;
        best = &p;
      }
    }
    if (best == nullptr || best_distance > params.roi_radius) return std::nullopt;
    std::normal_distribution<double> unit(0.0, 1.0);
    geometry::Pose2 seen = *best;
    if (params.position_noise > 0.0) {
      seen.x += params.position_noise * unit(*rng);
      seen.y += params.position_noise * unit(*rng);
    }
    if (params.yaw_noise > 0.0) seen.yaw = geometry::normalize_angle(seen.yaw + params.yaw_noise * unit(*rng));
    return seen;
  };
}

DockingRunResult simulate_docking(const geometry::Pose2& start, const geometry::Pose2& pallet,
                                  const DockingRunParams& params, std::uint64_t seed) {
  const geometry::Vec2 prior = pallet.position() + params.prior_error * row_direction(pallet);
  return simulate_docking(start, pallet, {prior.x, prior.y, pallet.yaw}, params,
                          make_simulated_detector(pallet, params.detector, seed));
}

DockingRunResult simulate_docking(const geometry::Pose2& start, const geometry::Pose2& pallet,
                                  const geometry::Pose2& pallet_prior, const DockingRunParams& params,
                                  const PalletDetector& detector) {
  DockingRunResult result;
  sim::Tricycle body(params.vehicle, start);
  DockingParams law_params = params.law;
  law_params.vehicle = params.vehicle.geometry;  // the law steers the stacker it drives
  geometry::Pose2 estimate = pose_sensor_reading(start, params.pose_noise, params.pose_seed);
  std::mt19937_64 odometry_rng(params.pose_seed ^ 0x9e3779b97f4a7c15ULL);
  DockingLaw law(law_params, pallet_prior, estimate);
  const double dt = params.control_period;
  double t = 0.0;
  double next_sample = 0.0;
  DockingOutput out;
  // The law bounds the run by its own time limit; the loop bound only guards against a stuck clock.
  const long max_steps = static_cast<long>(std::ceil((params.law.time_limit + 10.0) / dt));
  for (long i = 0; i < max_steps; ++i) {
    DockingInput in;
    in.vehicle = estimate;
    in.steer_angle = body.state().theta_steer;
    in.dt = dt;
    if (detector) {
      // The detector looks where the law expects the pallet relative to the vehicle; what it
      // finds is put in the map by the vehicle's estimate.
      const auto seen = detector(body.pose(), reframe(estimate, body.pose(), law.pallet_estimate()), t);
      if (seen) in.pallet_detection = reframe(body.pose(), estimate, *seen);
    }
    out = law.update(in);
    if (params.trajectory_period > 0.0 && t >= next_sample) {
      result.trajectory.push_back({t, body.pose(), out.command, out.phase});
      next_sample += params.trajectory_period;
    }
    if (out.phase == DockingPhase::kDone || out.phase == DockingPhase::kFailed) break;
    const geometry::Pose2 before = body.pose();
    body.step(out.command, dt);
    result.path_length += geometry::distance(before.position(), body.pose().position());
    estimate = odometry_step(estimate, before, body.pose(), params.odometry_noise, odometry_rng);
    t += dt;
  }
  result.final_phase = law.phase();
  result.completed = law.phase() == DockingPhase::kDone;
  result.failure_reason = out.failure_reason;
  if (!result.completed && result.failure_reason.empty()) result.failure_reason = "did not finish";
  result.time = t;
  result.realignments = law.realignments();
  result.detections = law.accepted_detections();
  result.final_pose = body.pose();

  // Errors against the true pallet.
  const geometry::Vec2 axis{std::cos(pallet.yaw), std::sin(pallet.yaw)};
  const geometry::Vec2 face = pallet.position() + (0.5 * params.law.pallet.depth) * axis;
  const geometry::Vec2 tip = sim::fork_tip_midpoint(body.pose(), params.vehicle.geometry) - face;
  result.lateral_error = geometry::dot(tip, row_direction(pallet));
  result.yaw_error = geometry::angle_diff(body.pose().yaw, pallet.yaw);
  result.depth_error = -geometry::dot(tip, axis) - params.law.pocket_depth;
  result.success = result.completed && std::abs(result.lateral_error) <= params.success_lateral &&
                   std::abs(result.yaw_error) <= params.success_yaw;
  if (result.completed && !result.success) result.failure_reason = "docked outside the lateral or yaw target";
  return result;
}

}  // namespace fleet::control
