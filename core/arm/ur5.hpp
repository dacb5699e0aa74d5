#pragma once

#include <Eigen/Geometry>
#include <array>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::arm {

inline constexpr int kJointCount = 6;

/// Joint angles θ1..θ6 in radians, in the sense and zero of the UR5's Denavit-Hartenberg frames
/// [Picker thesis, Table 1]: all zero is the arm stretched horizontally along the base's -x.
using JointVector = std::array<double, kJointCount>;

using geometry::kDeg;

/// UR5 link lengths in metres, standard (distal) DH [Picker thesis, Table 1]. The twists are fixed
/// by the UR geometry (α = π/2, 0, 0, π/2, -π/2, 0) because the analytic inverse relies on them.
/// a3 is the manufacturer's -0.39225: the thesis prints -0.39255, a transposition of two digits.
struct Ur5Geometry {
  double d1 = 0.089159;
  double a2 = -0.425;
  double a3 = -0.39225;
  double d4 = 0.10915;
  double d5 = 0.09465;
  double d6 = 0.0823;
};

/// Where the cups sit on the flange. The thesis draws the gripper (Picker thesis, Fig. 3.12) without its mounting;
/// Table 10 fits only a gripper whose cups face at right angles to the flange axis: θ6 ≠ 0 "breaks
/// the box away" only if turning about the flange axis tilts the box, i.e. if that axis is
/// horizontal while the cups face down; and only so does the arm reach 0.5 m below its base with
/// the box upright [Picker thesis, section 4.4.1]. The tool frame: origin at the centre of the cups' lips, z the
/// way the cups face (-y of the flange), x along the plate's length (x of the flange), y along the
/// flange axis.
struct ToolMount {
  double below_axis = 0.10;  ///< m from the flange axis to the lips, along -y of the flange
  double along_axis = 0.05;  ///< m from the flange face to the plate's centre, along the flange axis

  Eigen::Isometry3d flange_to_tool() const;
};

struct Ur5Config {
  Ur5Geometry geometry;
  ToolMount tool;
  /// Reach of the flange from the arm base (UR5 datasheet: 850 mm); [Picker thesis, Algorithm 4,
  /// step 6] stops before planning when a target is farther.
  double max_reach = 0.85;
};

/// One joint's allowed interval, radians, both ends included.
struct JointRange {
  double lower = 0.0;
  double upper = 0.0;
};

struct JointLimits {
  std::array<JointRange, kJointCount> ranges{};

  /// The UR5's own travel: ±360° on every joint.
  static JointLimits ur5_hardware();
  /// The ranges that keep the arm off its housing, short of full extension and the box upright
  /// [Picker thesis, Table 10]: θ1 ∈ [-175°, 60°], θ2 ∈ [-90°, 0°], θ3 ∈ [60°, 135°] (100° under
  /// constraint C), θ4 ∈ [-100°, 0°], θ5 ≤ 90°, θ6 = 0. The table gives θ5 no lower bound: the
  /// hardware's -360° is kept.
  static JointLimits picker_table10(bool constraint_c = false);
};

/// Comparisons with limits allow this much, so that a value the kinematics meant to be exactly on a
/// bound (θ6 = 0) is not refused for a rounding error.
inline constexpr double kLimitTolerance = 1e-9;

/// A joint outside its range. `joint` is 1-based, as the thesis numbers them.
struct LimitViolation {
  int joint = 0;
  double value = 0.0;
  JointRange range;

  /// "joint 3 at 142.13° outside [60.0°, 135.0°]"
  std::string describe() const;
};

/// The first joint outside its range, if any.
std::optional<LimitViolation> first_violation(const JointVector& q, const JointLimits& limits);

/// Shifts each joint by whole turns to the value inside its range nearest `reference` (a revolute
/// joint at θ and θ ± 2π is the same pose). Empty when some joint has no such value.
std::optional<JointVector> fit_to_limits(const JointVector& q, const JointVector& reference, const JointLimits& limits);

/// Which of several inverse solutions to use.
struct IkChoice {
  std::optional<JointVector> joints;  ///< the solution inside the limits nearest the current joints
  /// When none fits: the violation of the solution that misses its ranges by the least.
  std::optional<LimitViolation> nearest_violation;
};

/// The solution within `limits` nearest `current` in the Euclidean joint norm, after fitting whole
/// turns. Near the current joints means no wrist or elbow flip along a path.
IkChoice choose_nearest(const std::vector<JointVector>& solutions, const JointVector& current,
                        const JointLimits& limits);

/// Joint speed and acceleration. The UR5 moves each joint at up to 180°/s; the arm works slower.
/// Working speed and acceleration are URScript's movej defaults (1.05 rad/s, 1.4 rad/s²).
struct JointSpeedLimits {
  double max_speed = std::numbers::pi;  ///< rad/s, UR5 datasheet
  double working_speed = 1.05;          ///< rad/s, at most max_speed
  double acceleration = 1.4;            ///< rad/s²

  /// Throws std::invalid_argument naming the field when a value is not positive or the working
  /// speed exceeds the maximum.
  void validate() const;
};

/// Time to travel `distance` from rest to rest at most `speed`, accelerating and braking at
/// `acceleration` (a trapezoid, a triangle when too short to reach the speed).
double trapezoid_time(double distance, double speed, double acceleration);

/// Time of a synchronised joint move: every joint arrives together, so the joint with the longest
/// travel sets it.
double joint_move_time(const JointVector& from, const JointVector& to, const JointSpeedLimits& limits);

/// UR5 kinematics: forward [Picker thesis, eq. 3.8, 4.36-4.38] and the closed-form inverse of the
/// UR geometry (three parallel middle axes, offset wrist). Frames: the arm base frame of Table 1,
/// z up along joint 1; the flange frame 6; the tool frame of ToolMount at the cups' lips.
class Ur5 {
 public:
  /// Throws std::invalid_argument when a length is degenerate (a2, a3 or d6 zero, d4 negative, a
  /// non-positive reach).
  explicit Ur5(Ur5Config config = {});

  const Ur5Config& config() const { return config_; }

  /// Frames 1..6 in the arm base frame: the running product of eq. 3.8.
  std::array<Eigen::Isometry3d, kJointCount> link_frames(const JointVector& q) const;
  Eigen::Isometry3d flange_pose(const JointVector& q) const;
  Eigen::Isometry3d tool_pose(const JointVector& q) const;

  /// Every joint vector that puts the flange at `flange` (up to 8: shoulder left/right x wrist
  /// up/down x elbow up/down), each angle in [-π, π). None when the pose is out of reach. On the
  /// wrist singularity (θ5 = 0 or π, joints 4 and 6 aligned) θ6 is not determined and is set to
  /// `theta6_if_singular`.
  std::vector<JointVector> inverse(const Eigen::Isometry3d& flange, double theta6_if_singular = 0.0) const;
  std::vector<JointVector> inverse_tool(const Eigen::Isometry3d& tool, double theta6_if_singular = 0.0) const;

 private:
  Ur5Config config_;
};

/// A tool pose pointing straight down (the cups facing the floor) with the plate's length at `yaw`
/// about the vertical.
Eigen::Isometry3d top_down_tool_pose(const Eigen::Vector3d& position, double yaw);

/// Yaw of a tool pose's x axis (the plate's length) about the vertical.
double tool_yaw(const Eigen::Isometry3d& tool);

/// The angle of the rotation taking `a`'s orientation to `b`'s, radians.
double orientation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

}  // namespace fleet::arm
