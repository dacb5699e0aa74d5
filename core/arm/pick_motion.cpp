#include "arm/pick_motion.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <utility>

#include "geometry/pose.hpp"

namespace fleet::arm {

namespace {

constexpr double kPi = std::numbers::pi;

template <typename... Values>
std::string format(const char* pattern, Values... values) {
  char text[256];
  std::snprintf(text, sizeof text, pattern, values...);
  return text;
}

std::string describe_point(const Eigen::Vector3d& p) {
  return format("(%.3f, %.3f, %.3f) m", p.x(), p.y(), p.z());
}

void require_positive(double value, const char* name) {
  if (!(value > 0.0)) {
    throw std::invalid_argument(std::string("PickMotionConfig.") + name + " must be > 0, got " + std::to_string(value));
  }
}

struct WaypointSolution {
  std::optional<JointVector> joints;
  std::string failure;
};

/// [Picker thesis, Algorithm 4, steps 9-10]: the inverse solutions of the waypoint's pose, the one
/// within the limits nearest the previous waypoint's joints. The thesis checks |q| > 3.1 rad; its
/// Table 10 is the check it means ("otherwise a collision will result").
WaypointSolution solve_waypoint(const Ur5& arm, const JointLimits& limits, const CartesianWaypoint& waypoint,
                                const JointVector& previous) {
  const std::vector<JointVector> solutions = arm.inverse_tool(top_down_tool_pose(waypoint.position, waypoint.yaw), 0.0);
  if (solutions.empty()) return {std::nullopt, "out of the arm's reach (no inverse solution)"};
  const IkChoice choice = choose_nearest(solutions, previous, limits);
  if (choice.joints) return {choice.joints, ""};
  return {std::nullopt, "no inverse solution within [Picker thesis, Table 10]; the nearest has " +
                            choice.nearest_violation->describe()};
}

int steps_for(double change, double resolution) {
  return static_cast<int>(std::ceil(std::abs(change) / resolution - 1e-9));
}

/// The bearing of a point from the arm base axis.
double bearing(const Eigen::Vector3d& p) {
  return std::atan2(p.y(), p.x());
}

/// [Picker thesis, eq. 4.43-4.46]: the count from the largest coordinate change (the thesis
/// compares signed changes; their sizes are meant), the same fraction of every change per step.
/// A yaw change needs steps of its own: the thesis's count, from positions only, turns the wrist
/// in one step when the cups do not move.
std::vector<CartesianWaypoint> linear_waypoints(const CartesianWaypoint& start, const CartesianWaypoint& target,
                                                double yaw_change, const PickMotionConfig& config) {
  const Eigen::Vector3d delta = target.position - start.position;
  const int count = std::max({1, steps_for(delta.cwiseAbs().maxCoeff(), config.linear_resolution),
                              steps_for(yaw_change, config.angular_resolution)});
  std::vector<CartesianWaypoint> waypoints;
  for (int k = 1; k <= count; ++k) {
    const double s = static_cast<double>(k) / count;
    waypoints.push_back({start.position + s * delta, start.yaw + s * yaw_change});
  }
  waypoints.back().position = target.position;  // exact, free of rounding in the sum
  return waypoints;
}

/// [Picker thesis, Algorithm 4, step 8], circular branch: about the arm base axis, the bearing
/// swept by `sweep` while z and the yaw change linearly. The thesis holds the radius at the
/// target's from the first waypoint, a jump from the current radius; here it changes linearly too.
std::vector<CartesianWaypoint> circular_waypoints(const CartesianWaypoint& start, const CartesianWaypoint& target,
                                                  double sweep, double yaw_change, const PickMotionConfig& config) {
  const double start_radius = std::hypot(start.position.x(), start.position.y());
  const double dr = std::hypot(target.position.x(), target.position.y()) - start_radius;
  const double dz = target.position.z() - start.position.z();
  const double start_bearing = bearing(start.position);
  const int count =
      std::max({1, steps_for(sweep, config.angular_resolution), steps_for(yaw_change, config.angular_resolution),
                steps_for(dz, config.linear_resolution), steps_for(dr, config.linear_resolution)});
  std::vector<CartesianWaypoint> waypoints;
  for (int k = 1; k <= count; ++k) {
    const double s = static_cast<double>(k) / count;
    const double radius = start_radius + s * dr;
    const double angle = start_bearing + s * sweep;
    waypoints.push_back({{radius * std::cos(angle), radius * std::sin(angle), start.position.z() + s * dz},
                         start.yaw + s * yaw_change});
  }
  waypoints.back().position = target.position;
  return waypoints;
}

}  // namespace

void PickMotionConfig::validate() const {
  require_positive(approach_height, "approach_height");
  require_positive(linear_resolution, "linear_resolution");
  require_positive(angular_resolution, "angular_resolution");
  require_positive(circular_threshold, "circular_threshold");
  require_positive(max_joint_step, "max_joint_step");
  require_positive(tool_speed, "tool_speed");
  require_positive(tool_acceleration, "tool_acceleration");
  if (grip_time < 0.0 || release_time < 0.0) {
    throw std::invalid_argument(
        format("PickMotionConfig: grip_time %.3f s and release_time %.3f s must be >= 0", grip_time, release_time));
  }
  joint_speed.validate();
}

double MotionPlan::duration() const {
  double total = 0.0;
  for (const MotionSegment& segment : segments) total += segment.duration;
  return total;
}

PickMotionPlanner::PickMotionPlanner(Ur5 arm, VacuumGripper gripper, ArmMount mount, PickMotionConfig config)
    : arm_(std::move(arm)), gripper_(std::move(gripper)), mount_(std::move(mount)), config_(std::move(config)) {
  config_.validate();
  if (!(gripper_.config().acceleration > 0.0)) {
    throw std::invalid_argument("PickMotionPlanner: a gripper sized for no acceleration cannot carry a box");
  }
  if (const auto violation = first_violation(config_.home, config_.limits)) {
    throw std::invalid_argument("PickMotionConfig.home: " + violation->describe());
  }
  const Eigen::Vector3d tool_axis = arm_.tool_pose(config_.home).linear().col(2);
  if (tool_axis.z() > -1.0 + 1e-9) {
    throw std::invalid_argument("PickMotionConfig.home: the tool must point straight down");
  }
}

Eigen::Vector3d PickMotionPlanner::to_arm_frame(const Eigen::Vector3d& in_base) const {
  return Eigen::AngleAxisd(-mount_.yaw, Eigen::Vector3d::UnitZ()) * (in_base - mount_.position);
}

MoveResult PickMotionPlanner::plan_move(const std::string& name, const JointVector& from,
                                        const CartesianWaypoint& target, bool carrying) const {
  MoveResult result;
  result.segment.name = name;
  result.segment.carrying = carrying;
  const Eigen::Isometry3d start_pose = arm_.tool_pose(from);
  const CartesianWaypoint start{start_pose.translation(), tool_yaw(start_pose)};

  // [Picker thesis, Algorithm 4, step 6]: refuse a target beyond the arm's reach before planning.
  // The thesis's test reads "reach < threshold: return", the reverse of its prose; the prose is meant.
  const Eigen::Isometry3d target_flange =
      top_down_tool_pose(target.position, target.yaw) * arm_.config().tool.flange_to_tool().inverse();
  const double reach = target_flange.translation().norm();
  if (reach > arm_.config().max_reach) {
    result.reason = name + ": target " + describe_point(target.position) +
                    format(
                        " puts the flange %.3f m from the arm base, beyond the %.2f m reach "
                        "[Picker thesis, Algorithm 4, step 6]",
                        reach, arm_.config().max_reach);
    return result;
  }

  // [Picker thesis, Algorithm 4, steps 3 and 7]: the bearing about the arm base axis decides the
  // circle. The thesis writes θ = y/x, calls it the yaw and compares the signed change: atan2,
  // the bearing and the size of the change are meant.
  const bool has_bearing = std::hypot(start.position.x(), start.position.y()) > 1e-6 &&
                           std::hypot(target.position.x(), target.position.y()) > 1e-6;
  const double bearing_change =
      has_bearing ? geometry::angle_diff(bearing(target.position), bearing(start.position)) : 0.0;
  const bool circular = std::abs(bearing_change) > config_.circular_threshold;
  std::vector<double> sweeps{bearing_change};
  if (circular) sweeps.push_back(bearing_change - std::copysign(2.0 * kPi, bearing_change));
  // The plate turns with the arm (the thesis adds the yaw step to the bearing, step 8) and then by
  // the shortest remaining angle, which keeps the wrist's own turn (θ5) least; failing that, the
  // other way, for when the short turn runs θ5 into its bound.
  std::vector<std::pair<double, double>> attempts;  // bearing sweep, yaw change
  for (const double sweep : sweeps) {
    const double rest = geometry::angle_diff(target.yaw, start.yaw + sweep);
    attempts.emplace_back(sweep, sweep + rest);
    attempts.emplace_back(sweep, sweep + rest - std::copysign(2.0 * kPi, rest));
  }

  std::string first_failure;
  int refused = 0;
  for (const auto& [sweep, yaw_change] : attempts) {
    MotionSegment segment = result.segment;
    segment.circular = circular;
    segment.waypoints = circular ? circular_waypoints(start, target, sweep, yaw_change, config_)
                                 : linear_waypoints(start, target, yaw_change, config_);
    std::string failure;
    JointVector previous = from;
    const int count = static_cast<int>(segment.waypoints.size());
    for (int i = 0; i < count && failure.empty(); ++i) {
      const CartesianWaypoint& waypoint = segment.waypoints[static_cast<std::size_t>(i)];
      auto where = [&] {
        return name + format(": waypoint %d of %d at ", i + 1, count) + describe_point(waypoint.position) + ": ";
      };
      const WaypointSolution solved = solve_waypoint(arm_, config_.limits, waypoint, previous);
      if (!solved.joints) {
        failure = where() + solved.failure;
        break;
      }
      for (std::size_t j = 0; j < previous.size() && failure.empty(); ++j) {
        const double step = std::abs((*solved.joints)[j] - previous[j]);
        if (step > config_.max_joint_step) {
          failure =
              where() + format("joint %d turns %.1f° from the previous waypoint (a jump to another branch or turn)",
                               static_cast<int>(j) + 1, step / kDeg);
        }
      }
      segment.joints.push_back(*solved.joints);
      previous = *solved.joints;
    }
    if (failure.empty()) {
      segment.duration = segment_duration(start.position, from, segment, carrying);
      result.segment = std::move(segment);
      result.ok = true;
      return result;
    }
    if (refused++ == 0) first_failure = failure;
  }
  // The shortest way's refusal says most; the others are counted.
  result.reason = first_failure + format(" (%d other way%s round refused too)", refused - 1, refused > 2 ? "s" : "");
  return result;
}

double PickMotionPlanner::segment_duration(const Eigen::Vector3d& start, const JointVector& start_joints,
                                           const MotionSegment& segment, bool carrying) const {
  const JointSpeedLimits& joint = config_.joint_speed;
  const double design_acceleration = gripper_.config().acceleration;
  // Cruise time: each step as slow as its slowest limit (the leading joint at the working speed,
  // the tool at its speed; on a circle with a box, the centripetal acceleration within the one
  // the gripper was sized for [Picker thesis, eq. 3.10-3.12]).
  double cruise = 0.0;
  Eigen::Vector3d previous_point = start;
  JointVector previous_joints = start_joints;
  for (std::size_t i = 0; i < segment.waypoints.size(); ++i) {
    double joint_step = 0.0;
    for (std::size_t j = 0; j < previous_joints.size(); ++j) {
      joint_step = std::max(joint_step, std::abs(segment.joints[i][j] - previous_joints[j]));
    }
    const Eigen::Vector3d& point = segment.waypoints[i].position;
    const double tool_step = (point - previous_point).norm();
    double step_time = std::max(joint_step / joint.working_speed, tool_step / config_.tool_speed);
    if (carrying && segment.circular) {
      const double radius = std::hypot(point.x(), point.y());
      if (radius > 0.0) step_time = std::max(step_time, tool_step / std::sqrt(design_acceleration * radius));
    }
    cruise += step_time;
    previous_point = point;
    previous_joints = segment.joints[i];
  }
  // Start and stop at rest: add the longer of the joint and tool ramps (a trapezoid in the path's
  // progress, a triangle when the move is too short to reach cruise).
  const double tool_acceleration =
      carrying ? std::min(config_.tool_acceleration, design_acceleration) : config_.tool_acceleration;
  const double ramp = std::max(joint.working_speed / joint.acceleration, config_.tool_speed / tool_acceleration);
  if (cruise <= 0.0) return 0.0;
  return cruise >= ramp ? cruise + ramp : 2.0 * std::sqrt(cruise * ramp);
}

MotionPlan PickMotionPlanner::plan_sequence(const CartesianWaypoint& grip, bool picking) const {
  MotionPlan plan;
  const CartesianWaypoint above{grip.position + Eigen::Vector3d(0.0, 0.0, config_.approach_height), grip.yaw};
  const Eigen::Isometry3d home_pose = arm_.tool_pose(config_.home);
  const CartesianWaypoint home{home_pose.translation(), tool_yaw(home_pose)};
  JointVector joints = config_.home;
  auto append_move = [&](const std::string& name, const CartesianWaypoint& target, bool carrying) {
    MoveResult move = plan_move(name, joints, target, carrying);
    if (!move.ok) {
      plan.reason = move.reason;
      return false;
    }
    joints = move.segment.joints.back();
    plan.segments.push_back(std::move(move.segment));
    return true;
  };

  // A pick carries the box from the ascent on, a drop until the pump stops.
  if (!append_move(picking ? "reach above the box" : "reach above the place", above, !picking)) return plan;
  if (!append_move("descend", grip, !picking)) return plan;
  MotionSegment dwell;
  dwell.name = picking ? "pump on" : "pump off";
  dwell.kind = picking ? SegmentKind::kVacuumOn : SegmentKind::kVacuumOff;
  dwell.carrying = true;
  dwell.joints.push_back(joints);
  dwell.duration = picking ? config_.grip_time : config_.release_time;
  plan.segments.push_back(dwell);
  if (!append_move("ascend", above, picking)) return plan;
  if (!append_move("return home", home, picking)) return plan;

  for (std::size_t j = 0; j < joints.size(); ++j) {
    if (std::abs(joints[j] - config_.home[j]) > 1e-6) {
      plan.reason = format("return home: arrives with joint %d at %.1f° instead of the home's %.1f°",
                           static_cast<int>(j) + 1, joints[j] / kDeg, config_.home[j] / kDeg);
      return plan;
    }
  }
  plan.ok = true;
  return plan;
}

MotionPlan PickMotionPlanner::plan_first_feasible(const Eigen::Vector3d& grip, const std::vector<double>& yaws,
                                                  bool picking) const {
  MotionPlan first_refusal;
  for (const double yaw : yaws) {
    MotionPlan plan = plan_sequence({grip, yaw}, picking);
    if (plan.ok) return plan;
    if (first_refusal.reason.empty()) first_refusal = std::move(plan);
  }
  return first_refusal;
}

MotionPlan PickMotionPlanner::plan_pick(const BoxPlacement& placement) const {
  const Eigen::Vector3d grip = to_arm_frame(placement.top_centre);
  const double box_yaw = placement.yaw - mount_.yaw;
  // The plate along the box's length or across it, each two ways round: the ways the face takes,
  // ordered by the wrist turn from home (the plate turning with the arm costs the wrist nothing).
  const Eigen::Isometry3d home_pose = arm_.tool_pose(config_.home);
  const double yaw_with_arm =
      tool_yaw(home_pose) + geometry::angle_diff(bearing(grip), bearing(home_pose.translation()));
  std::vector<std::pair<double, double>> candidates;  // wrist turn, plate yaw on the box
  GripCheck refusal;
  for (int quarter = 0; quarter < 4; ++quarter) {
    const double on_box = quarter * kPi / 2.0;
    const GripCheck check = gripper_.can_hold(placement.box, on_box);
    if (!check.ok) {
      if (refusal.reason.empty()) refusal = check;
      continue;
    }
    candidates.emplace_back(std::abs(geometry::angle_diff(box_yaw + on_box, yaw_with_arm)), on_box);
  }
  if (candidates.empty()) {
    MotionPlan refused;
    refused.reason = "grip: " + refusal.reason;
    return refused;
  }
  std::sort(candidates.begin(), candidates.end());
  MotionPlan first_refusal;
  for (const auto& [turn, on_box] : candidates) {
    MotionPlan plan = plan_sequence({grip, box_yaw + on_box}, true);
    plan.plate_yaw_on_box = on_box;
    if (plan.ok) return plan;
    if (first_refusal.reason.empty()) first_refusal = std::move(plan);
  }
  return first_refusal;
}

MotionPlan PickMotionPlanner::plan_drop(const Box& box, const DropPlacement& placement, double plate_yaw_on_box) const {
  const GripCheck check = gripper_.can_hold(box, plate_yaw_on_box);
  if (!check.ok) {
    MotionPlan refused;
    refused.reason = "grip: " + check.reason;
    return refused;
  }
  const Eigen::Vector3d grip = to_arm_frame(placement.bottom_centre) + Eigen::Vector3d(0.0, 0.0, box.height);
  const double yaw = placement.yaw - mount_.yaw + plate_yaw_on_box;
  // A box stands the same turned half round, so the plate may arrive either way.
  MotionPlan plan = plan_first_feasible(grip, {yaw, yaw + kPi}, false);
  plan.plate_yaw_on_box = plate_yaw_on_box;
  return plan;
}

}  // namespace fleet::arm
