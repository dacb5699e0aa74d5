#include "arm/pick_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/pose.hpp"

using namespace fleet::arm;

namespace {

// Positions in the mobile base's frame (x forward, y left, z up from the floor); the arm base is
// 0.80 m above its centre. The home pose holds the cups 0.38 m to the left.
const Box kBox{3.0, 0.30, 0.30, 0.25};
const Eigen::Vector3d kSideTop{0.0, 0.55, 0.60};   // beside the robot, a short reach from home
const Eigen::Vector3d kRearTop{-0.50, 0.0, 0.60};  // behind it: 74° round from home, a circular move
const Eigen::Vector3d kDropBottom{0.40, 0.30, 0.45};

PickMotionPlanner make_planner() {
  return PickMotionPlanner(Ur5{}, VacuumGripper{});
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

/// Every waypoint's joints put the cups where the waypoint says, facing down, within Table 10.
void expect_consistent(const PickMotionPlanner& planner, const MotionPlan& plan) {
  for (const MotionSegment& segment : plan.segments) {
    if (segment.kind != SegmentKind::kMove) continue;
    ASSERT_EQ(segment.joints.size(), segment.waypoints.size()) << segment.name;
    for (std::size_t i = 0; i < segment.joints.size(); ++i) {
      const Eigen::Isometry3d expected = top_down_tool_pose(segment.waypoints[i].position, segment.waypoints[i].yaw);
      const Eigen::Isometry3d actual = planner.arm().tool_pose(segment.joints[i]);
      ASSERT_LT((actual.translation() - expected.translation()).norm(), 1e-9) << segment.name << " " << i;
      ASSERT_LT(orientation_error(actual, expected), 1e-9) << segment.name << " " << i;
      ASSERT_FALSE(first_violation(segment.joints[i], planner.config().limits)) << segment.name << " " << i;
      ASSERT_NEAR(segment.joints[i][5], 0.0, kLimitTolerance);
    }
  }
}

std::vector<std::string> segment_names(const MotionPlan& plan) {
  std::vector<std::string> names;
  for (const MotionSegment& segment : plan.segments) names.push_back(segment.name);
  return names;
}

void print_plan(const char* label, const MotionPlan& plan) {
  std::printf("[%s] %.2f s\n", label, plan.duration());
  for (const MotionSegment& segment : plan.segments) {
    std::printf("  %-22s %3zu waypoints %-8s %5.2f s\n", segment.name.c_str(), segment.waypoints.size(),
                segment.circular ? "circular" : "", segment.duration);
  }
}

}  // namespace

TEST(PickMotion, PickInReachFollowsTheThesisSequence) {
  const PickMotionPlanner planner = make_planner();
  const MotionPlan plan = planner.plan_pick({kBox, kSideTop, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  EXPECT_EQ(segment_names(plan),
            (std::vector<std::string>{"reach above the box", "descend", "pump on", "ascend", "return home"}));
  expect_consistent(planner, plan);

  // 20 cm above the top face, then down onto it [Picker thesis, section 5.3.3.1.2].
  const Eigen::Vector3d grip = planner.to_arm_frame(kSideTop);
  EXPECT_LT((plan.segments[0].waypoints.back().position - (grip + Eigen::Vector3d(0, 0, 0.20))).norm(), 1e-12);
  EXPECT_LT((plan.segments[1].waypoints.back().position - grip).norm(), 1e-12);
  EXPECT_EQ(plan.segments[2].kind, SegmentKind::kVacuumOn);
  EXPECT_FALSE(plan.segments[1].carrying);
  EXPECT_TRUE(plan.segments[3].carrying);
  for (std::size_t j = 0; j < kJointCount; ++j) {
    EXPECT_NEAR(plan.segments.back().joints.back()[j], planner.config().home[j], 1e-6);
  }
  for (const MotionSegment& segment : plan.segments) EXPECT_GT(segment.duration, 0.0) << segment.name;
}

TEST(PickMotion, ABoxOutOfReachIsRejectedWithItsReason) {
  const PickMotionPlanner planner = make_planner();
  const MotionPlan plan = planner.plan_pick({kBox, {0.0, 1.20, 0.60}, 0.0});
  EXPECT_FALSE(plan.ok);
  EXPECT_TRUE(plan.segments.empty());
  EXPECT_TRUE(contains(plan.reason, "reach above the box")) << plan.reason;
  EXPECT_TRUE(contains(plan.reason, "beyond the 0.85 m reach")) << plan.reason;
}

TEST(PickMotion, AWaypointBeyondTheLimitsNamesTheWaypointAndTheJoint) {
  const PickMotionPlanner planner = make_planner();
  // 0.3 m above the floor next to the robot: the shoulder would have to drop below horizontal.
  const MotionPlan plan = planner.plan_pick({kBox, {0.0, 0.30, 0.30}, 0.0});
  EXPECT_FALSE(plan.ok);
  EXPECT_TRUE(contains(plan.reason, "waypoint")) << plan.reason;
  EXPECT_TRUE(contains(plan.reason, "Table 10")) << plan.reason;
  EXPECT_TRUE(contains(plan.reason, "joint 2")) << plan.reason;
}

TEST(PickMotion, ReachesBoxTopsBesideTheRobotBetween35And90cmHigh) {
  const PickMotionPlanner planner = make_planner();
  auto can_pick = [&](double y, double z) { return planner.plan_pick({kBox, {0.0, y, z}, 0.0}).ok; };
  for (const double z : {0.35, 0.45, 0.60, 0.75, 0.90}) EXPECT_TRUE(can_pick(0.55, z)) << z;
  EXPECT_FALSE(can_pick(0.55, 0.30));  // the elbow would open below θ3 = 60°
  EXPECT_FALSE(can_pick(0.55, 0.95));  // on the way 20 cm above it, θ4 would pass 0°
  EXPECT_TRUE(can_pick(0.22, 0.60));
  EXPECT_TRUE(can_pick(0.83, 0.60));
  EXPECT_FALSE(can_pick(0.18, 0.60));  // the elbow would fold beyond θ3 = 135°
  EXPECT_FALSE(can_pick(0.88, 0.60));  // beyond the 0.85 m reach
}

TEST(PickMotion, ATooHeavyBoxIsRefusedBeforeMoving) {
  const PickMotionPlanner planner = make_planner();
  const MotionPlan plan = planner.plan_pick({{6.0, 0.30, 0.30, 0.25}, kSideTop, 0.0});
  EXPECT_FALSE(plan.ok);
  EXPECT_TRUE(plan.segments.empty());
  EXPECT_TRUE(contains(plan.reason, "grip:")) << plan.reason;
  EXPECT_TRUE(contains(plan.reason, "payload")) << plan.reason;
}

TEST(PickMotion, LinearWaypointsStepByTheLargestChange) {
  const PickMotionPlanner planner = make_planner();
  const JointVector& home = planner.config().home;
  const Eigen::Isometry3d start = planner.arm().tool_pose(home);
  const Eigen::Vector3d delta(0.03, -0.10, 0.02);
  const MoveResult move = planner.plan_move("shift", home, {start.translation() + delta, tool_yaw(start)}, false);
  ASSERT_TRUE(move.ok) << move.reason;
  EXPECT_FALSE(move.segment.circular);
  // [Picker thesis, eq. 4.44-4.46]: 0.10 m / 5 mm = 20 equal steps of Δ/20 on every axis.
  ASSERT_EQ(move.segment.waypoints.size(), 20u);
  Eigen::Vector3d previous = start.translation();
  for (const CartesianWaypoint& waypoint : move.segment.waypoints) {
    EXPECT_LT((waypoint.position - previous - delta / 20.0).norm(), 1e-12);
    previous = waypoint.position;
  }
}

TEST(PickMotion, ALargeBearingChangeMovesOnACircle) {
  const PickMotionPlanner planner = make_planner();
  const MotionPlan plan = planner.plan_pick({kBox, kRearTop, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  expect_consistent(planner, plan);
  const MotionSegment& reach = plan.segments.front();
  EXPECT_TRUE(reach.circular);
  EXPECT_FALSE(plan.segments[1].circular);  // the descent is straight down
  // The radius changes steadily from the start's to the target's, the bearing turns one way.
  const Eigen::Vector3d start = planner.arm().tool_pose(planner.config().home).translation();
  const double r0 = std::hypot(start.x(), start.y());
  const double r1 = std::hypot(reach.waypoints.back().position.x(), reach.waypoints.back().position.y());
  double previous_bearing = std::atan2(start.y(), start.x());
  for (const CartesianWaypoint& waypoint : reach.waypoints) {
    const double r = std::hypot(waypoint.position.x(), waypoint.position.y());
    EXPECT_GE(r, std::min(r0, r1) - 1e-9);
    EXPECT_LE(r, std::max(r0, r1) + 1e-9);
    const double bearing = std::atan2(waypoint.position.y(), waypoint.position.x());
    EXPECT_GT(fleet::geometry::angle_diff(bearing, previous_bearing), 0.0);
    previous_bearing = bearing;
  }
  // A short move from the side box stays straight.
  EXPECT_FALSE(planner.plan_pick({kBox, kSideTop, 0.0}).segments.front().circular);
}

TEST(PickMotion, ACircleGoesTheLongWayWhenTheShortWayLeavesTheBaseJointsRange) {
  const PickMotionPlanner planner = make_planner();
  // Behind on the right (bearing 225°) to ahead (bearing 11°): the short way, 146° through the
  // front right, needs θ1 beyond 60°; the long way, 214° round the left, stays inside.
  const MoveResult to_rear_right =
      planner.plan_move("to the rear right", planner.config().home, {{-0.40, -0.40, -0.10}, 0.0}, false);
  ASSERT_TRUE(to_rear_right.ok) << to_rear_right.reason;
  const MoveResult round =
      planner.plan_move("round", to_rear_right.segment.joints.back(), {{0.50, 0.10, -0.10}, 0.0}, false);
  ASSERT_TRUE(round.ok) << round.reason;
  EXPECT_TRUE(round.segment.circular);
  double swept = 0.0;
  Eigen::Vector3d previous(-0.40, -0.40, -0.10);
  for (const CartesianWaypoint& waypoint : round.segment.waypoints) {
    swept += fleet::geometry::angle_diff(std::atan2(waypoint.position.y(), waypoint.position.x()),
                                         std::atan2(previous.y(), previous.x()));
    previous = waypoint.position;
  }
  EXPECT_NEAR(swept / kDeg, -214.0, 1.0);
}

TEST(PickMotion, DropPutsTheBoxDownAndReturnsHome) {
  const PickMotionPlanner planner = make_planner();
  const MotionPlan pick = planner.plan_pick({kBox, kSideTop, 0.0});
  ASSERT_TRUE(pick.ok) << pick.reason;
  const MotionPlan drop = planner.plan_drop(kBox, {kDropBottom, 0.0}, pick.plate_yaw_on_box);
  ASSERT_TRUE(drop.ok) << drop.reason;
  expect_consistent(planner, drop);
  EXPECT_EQ(segment_names(drop),
            (std::vector<std::string>{"reach above the place", "descend", "pump off", "ascend", "return home"}));
  EXPECT_TRUE(drop.segments[0].carrying);
  EXPECT_FALSE(drop.segments[3].carrying);
  // The cups stop a box height above the place.
  const Eigen::Vector3d grip = planner.to_arm_frame(kDropBottom) + Eigen::Vector3d(0, 0, kBox.height);
  EXPECT_LT((drop.segments[1].waypoints.back().position - grip).norm(), 1e-12);
}

TEST(PickMotion, ReportsPickAndDropDurations) {
  const PickMotionPlanner planner = make_planner();
  const MotionPlan side = planner.plan_pick({kBox, kSideTop, 0.0});
  const MotionPlan rear = planner.plan_pick({kBox, kRearTop, 0.0});
  const MotionPlan drop = planner.plan_drop(kBox, {kDropBottom, 0.0}, side.plate_yaw_on_box);
  ASSERT_TRUE(side.ok && rear.ok && drop.ok);
  print_plan("pick beside", side);
  print_plan("pick behind", rear);
  print_plan("drop", drop);
  for (const MotionPlan* plan : {&side, &rear, &drop}) {
    double sum = 0.0;
    for (const MotionSegment& segment : plan->segments) sum += segment.duration;
    EXPECT_NEAR(plan->duration(), sum, 1e-12);
    EXPECT_GT(plan->duration(), 3.0);
    EXPECT_LT(plan->duration(), 60.0);
  }
  EXPECT_GT(rear.duration(), side.duration());  // the longer way round
}

TEST(PickMotion, CarryingAtTheGrippersDesignAccelerationTakesLonger) {
  PickMotionConfig config;
  config.joint_speed.acceleration = 10.0;  // let the tool's ramp set the pace
  const PickMotionPlanner planner(Ur5{}, VacuumGripper{}, ArmMount{}, config);
  const MotionPlan plan = planner.plan_pick({kBox, kSideTop, 0.0});
  ASSERT_TRUE(plan.ok) << plan.reason;
  // The descent (empty) and the ascent (with the box) cover the same 20 cm.
  EXPECT_GT(plan.segments[3].duration, plan.segments[1].duration + 0.1);
}

TEST(PickMotion, AHomeOutsideTheLimitsOrNotFacingDownIsRefused) {
  PickMotionConfig outside;
  outside.home = {-90 * kDeg, -70 * kDeg, 140 * kDeg, -70 * kDeg, -90 * kDeg, 0.0};
  EXPECT_THROW(PickMotionPlanner(Ur5{}, VacuumGripper{}, ArmMount{}, outside), std::invalid_argument);
  PickMotionConfig tilted;
  tilted.home = {-90 * kDeg, -70 * kDeg, 90 * kDeg, -40 * kDeg, -90 * kDeg, 0.0};
  EXPECT_THROW(PickMotionPlanner(Ur5{}, VacuumGripper{}, ArmMount{}, tilted), std::invalid_argument);
  PickMotionConfig bad;
  bad.linear_resolution = 0.0;
  EXPECT_THROW(PickMotionPlanner(Ur5{}, VacuumGripper{}, ArmMount{}, bad), std::invalid_argument);
}
