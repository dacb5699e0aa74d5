#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "arm/ur5.hpp"
#include "arm/vacuum_gripper.hpp"

namespace fleet::arm {

/// Where the arm base sits on the mobile base, in the mobile base's frame (x forward, y left, z up
/// from the floor). 0.80 m above the floor [Picker thesis, section 4.4.1]; the thesis gives no
/// horizontal position or yaw, so the arm is centred and aligned with the base.
struct ArmMount {
  Eigen::Vector3d position{0.0, 0.0, 0.80};  ///< m
  double yaw = 0.0;                          ///< rad
};

/// Settings of the Cartesian planner of [Picker thesis, Algorithm 4] and of the pick and drop
/// sequences, fixed per planner.
struct PickMotionConfig {
  /// The pose the arm rests in between picks, the cups facing down (θ2 + θ3 + θ4 = 0). The thesis
  /// shows it in Fig. 4.74 without values; this one keeps every joint 20° or more inside its
  /// [Picker thesis, Table 10] range, the cups 0.16 m above the arm base, 0.38 m to its left and 0.11 m behind.
  JointVector home{-90.0 * kDeg, -70.0 * kDeg, 90.0 * kDeg, -20.0 * kDeg, -90.0 * kDeg, 0.0};
  double approach_height = 0.20;  ///< m above the grip, "20 cm above the package" [Picker thesis, section 5.3.3.1.2]
  /// Waypoint spacing: the largest of |Δx|, |Δy|, |Δz| over this sets the count [Picker thesis, eq. 4.44]. The
  /// thesis leaves "res" unvalued.
  double linear_resolution = 0.005;         ///< m
  double angular_resolution = 1.0 * kDeg;   ///< rad per waypoint on a circular move
  double circular_threshold = 60.0 * kDeg;  ///< circular move above this yaw change
                                            ///< [Picker thesis, Algorithm 4, step 7]
  /// A joint that turns more than this between two neighbouring waypoints means the inverse jumped
  /// to another branch (a wrist or elbow flip), which the arm would not follow along the path.
  double max_joint_step = 10.0 * kDeg;  ///< rad
  double tool_speed = 0.25;             ///< m/s, URScript's movel default
  double tool_acceleration = 1.2;       ///< m/s², URScript's movel default
  double grip_time = 0.5;               ///< s from pump on to a held box; the thesis gives none
  double release_time = 0.5;            ///< s from pump off to a free box; the thesis gives none
  JointSpeedLimits joint_speed;
  JointLimits limits = JointLimits::picker_table10();

  /// Throws std::invalid_argument naming the field for a non-positive resolution, step, speed or
  /// height, or a negative dwell.
  void validate() const;
};

enum class SegmentKind { kMove, kVacuumOn, kVacuumOff };

/// A waypoint of [Picker thesis, Algorithm 4, step 8]: the cups' centre in the arm base frame and
/// the yaw of the plate's length, the cups facing down.
struct CartesianWaypoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< m
  double yaw = 0.0;                                    ///< rad
};

/// One step of a pick or drop: a Cartesian move, or a dwell while the pump starts or stops.
struct MotionSegment {
  std::string name;
  SegmentKind kind = SegmentKind::kMove;
  bool circular = false;                     ///< moved on a circle about the arm base axis
                                             ///< [Picker thesis, Algorithm 4, step 8]
  bool carrying = false;                     ///< a box hangs from the cups
  std::vector<CartesianWaypoint> waypoints;  ///< the start excluded
  std::vector<JointVector> joints;           ///< one per waypoint (a dwell: the joints it holds)
  double duration = 0.0;                     ///< s
};

/// A single Cartesian move, or why it cannot be made.
struct MoveResult {
  bool ok = false;
  std::string reason;
  MotionSegment segment;
};

/// A pick or drop sequence, or why it cannot be done.
struct MotionPlan {
  bool ok = false;
  std::string reason;  ///< empty when ok; names the segment, the waypoint and the joint
  std::vector<MotionSegment> segments;
  /// The plate's yaw from the box's length while held (a multiple of 90°): pass it to plan_drop.
  double plate_yaw_on_box = 0.0;

  double duration() const;  ///< s, all segments
};

/// A box to pick: the centre of its top face and its yaw, in the mobile base's frame.
struct BoxPlacement {
  Box box;
  Eigen::Vector3d top_centre = Eigen::Vector3d::Zero();  ///< m
  double yaw = 0.0;                                      ///< rad
};

/// Where to put a held box down: the centre of its bottom face and its yaw, in the mobile base's frame.
struct DropPlacement {
  Eigen::Vector3d bottom_centre = Eigen::Vector3d::Zero();  ///< m
  double yaw = 0.0;                                         ///< rad
};

/// Plans the arm's pick and drop [Picker thesis, section 4.4.2, Algorithm 4]: Cartesian waypoints
/// with the tool pointing down, an inverse solution at each, all within the Table 10 limits, and a
/// duration for each step from the joint and tool speed limits.
class PickMotionPlanner {
 public:
  /// Throws std::invalid_argument when the configuration is invalid, or when the home pose is
  /// outside the limits or its tool does not point down.
  PickMotionPlanner(Ur5 arm, VacuumGripper gripper, ArmMount mount = {}, PickMotionConfig config = {});

  const Ur5& arm() const { return arm_; }
  const VacuumGripper& gripper() const { return gripper_; }
  const PickMotionConfig& config() const { return config_; }

  /// A point of the mobile base's frame in the arm base frame.
  Eigen::Vector3d to_arm_frame(const Eigen::Vector3d& in_base) const;

  /// [Picker thesis, Algorithm 4]: from the joints `from` to the cups at `target` (arm base
  /// frame). A straight line split by the largest coordinate change or, when the bearing from the
  /// arm base axis changes by more than circular_threshold, a circular move about that axis (the
  /// other way round when the short way crosses the joint limits). `carrying` holds the tool's
  /// acceleration to the one the gripper was sized for.
  MoveResult plan_move(const std::string& name, const JointVector& from, const CartesianWaypoint& target,
                       bool carrying) const;

  /// Home -> approach_height above the top face -> descend -> pump on -> ascend -> home
  /// [Picker thesis, section 5.3.3.1.2]. The plate is laid along the box's length or across it,
  /// whichever the face takes and the arm reaches with the least wrist turn. Refused, with the
  /// reason, when the gripper cannot hold the box or no move can be made.
  MotionPlan plan_pick(const BoxPlacement& placement) const;

  /// The same with a held box: home -> above the place -> descend until the box stands on it ->
  /// pump off -> ascend -> home. `plate_yaw_on_box` is the pick's MotionPlan::plate_yaw_on_box.
  MotionPlan plan_drop(const Box& box, const DropPlacement& placement, double plate_yaw_on_box = 0.0) const;

 private:
  MotionPlan plan_sequence(const CartesianWaypoint& grip, bool picking) const;
  MotionPlan plan_first_feasible(const Eigen::Vector3d& grip, const std::vector<double>& yaws, bool picking) const;
  double segment_duration(const Eigen::Vector3d& start, const JointVector& start_joints, const MotionSegment& segment,
                          bool carrying) const;

  Ur5 arm_;
  VacuumGripper gripper_;
  ArmMount mount_;
  PickMotionConfig config_;
};

}  // namespace fleet::arm
