#include "arm/ur5.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "geometry/pose.hpp"

using namespace fleet::arm;

namespace {

constexpr double kPi = std::numbers::pi;

/// The flange position written out in [Picker thesis, eq. 4.36-4.38], independent of the DH product.
Eigen::Vector3d thesis_flange_position(const JointVector& q, const Ur5Geometry& g) {
  const double c1 = std::cos(q[0]), s1 = std::sin(q[0]);
  const double c2 = std::cos(q[1]), s2 = std::sin(q[1]);
  const double c4 = std::cos(q[3]), s4 = std::sin(q[3]);
  const double c5 = std::cos(q[4]), s5 = std::sin(q[4]);
  const double c23 = std::cos(q[1] + q[2]), s23 = std::sin(q[1] + q[2]);
  const double px = g.d6 * (c1 * s4 * s5 * s23 - c1 * c4 * s5 * c23 + s1 * c5) +
                    g.d5 * (c1 * s4 * c23 + c1 * c4 * s23) + g.a3 * c1 * c23 + g.d4 * s1 + g.a2 * c1 * c2;
  const double py = g.d6 * (s1 * s4 * s5 * s23 - s1 * c4 * s5 * c23 - c1 * c5) +
                    g.d5 * (s1 * s4 * c23 + s1 * c4 * s23) + g.a3 * s1 * c23 - g.d4 * c1 + g.a2 * s1 * c2;
  const double pz = -g.d6 * s5 * (c4 * s23 + s4 * c23) + g.d5 * (s4 * s23 - c4 * c23) + g.a3 * s23 + g.a2 * s2 + g.d1;
  return {px, py, pz};
}

JointVector random_joints(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  JointVector q{};
  for (double& v : q) v = angle(rng);
  return q;
}

double largest_joint_difference(const JointVector& a, const JointVector& b) {
  double largest = 0.0;
  for (std::size_t j = 0; j < a.size(); ++j) {
    largest = std::max(largest, std::abs(fleet::geometry::angle_diff(a[j], b[j])));
  }
  return largest;
}

}  // namespace

TEST(Ur5, ForwardMatchesTheThesisClosedForm) {
  const Ur5 arm;
  std::mt19937_64 rng(7);
  for (int i = 0; i < 500; ++i) {
    const JointVector q = random_joints(rng);
    const Eigen::Vector3d expected = thesis_flange_position(q, arm.config().geometry);
    EXPECT_LT((arm.flange_pose(q).translation() - expected).norm(), 1e-12);
  }
}

TEST(Ur5, ZeroPoseStretchesAlongMinusX) {
  const Ur5 arm;
  const Ur5Geometry& g = arm.config().geometry;
  const Eigen::Isometry3d flange = arm.flange_pose({0, 0, 0, 0, 0, 0});
  EXPECT_NEAR(flange.translation().x(), g.a2 + g.a3, 1e-12);
  EXPECT_NEAR(flange.translation().y(), -(g.d4 + g.d6), 1e-12);
  EXPECT_NEAR(flange.translation().z(), g.d1 - g.d5, 1e-12);
  EXPECT_DOUBLE_EQ(g.a3, -0.39225);  // the manufacturer's value, not the thesis's misprinted -0.39255
}

TEST(Ur5, InverseRecoversRandomJointVectors) {
  const Ur5 arm;
  const Ur5Geometry& g = arm.config().geometry;
  std::mt19937_64 rng(11);
  int checked = 0;
  int eight_solutions = 0;
  while (checked < 3000) {
    const JointVector q = random_joints(rng);
    const Eigen::Isometry3d flange = arm.flange_pose(q);
    // Away from the singular sets where the joints are not determined by the pose: the wrist
    // (θ5 = 0, π), the straight elbow (θ3 = 0, π) and the wrist centre on the shoulder's cylinder.
    const Eigen::Vector3d p5 = arm.link_frames(q)[4].translation();
    if (std::abs(std::sin(q[4])) < 0.01 || std::abs(std::sin(q[2])) < 0.01 ||
        std::hypot(p5.x(), p5.y()) < g.d4 + 0.01) {
      continue;
    }
    ++checked;
    const std::vector<JointVector> solutions = arm.inverse(flange);
    ASSERT_FALSE(solutions.empty());
    ASSERT_LE(solutions.size(), 8u);
    if (solutions.size() == 8u) ++eight_solutions;
    double closest = 1e9;
    for (const JointVector& s : solutions) {
      const Eigen::Isometry3d back = arm.flange_pose(s);
      ASSERT_LT((back.translation() - flange.translation()).norm(), 1e-6);
      ASSERT_LT(orientation_error(back, flange), 1e-6);
      closest = std::min(closest, largest_joint_difference(s, q));
    }
    EXPECT_LT(closest, 1e-6) << "the joints the pose came from are not among its solutions";
  }
  EXPECT_GT(eight_solutions, 2000);
}

TEST(Ur5, ToolInverseMapsBackThroughTheToolFrame) {
  const Ur5 arm;
  std::mt19937_64 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Isometry3d tool = arm.tool_pose(random_joints(rng));
    for (const JointVector& s : arm.inverse_tool(tool)) {
      const Eigen::Isometry3d back = arm.tool_pose(s);
      ASSERT_LT((back.translation() - tool.translation()).norm(), 1e-6);
      ASSERT_LT(orientation_error(back, tool), 1e-6);
    }
  }
}

TEST(Ur5, WristSingularityTakesTheGivenTheta6) {
  const Ur5 arm;
  const JointVector q{0.3, -1.0, 1.2, -0.4, 0.0, 0.7};  // θ5 = 0: joints 4 and 6 aligned
  const Eigen::Isometry3d flange = arm.flange_pose(q);
  const std::vector<JointVector> solutions = arm.inverse(flange, 0.25);
  ASSERT_FALSE(solutions.empty());
  bool took_given = false;
  for (const JointVector& s : solutions) {
    const Eigen::Isometry3d back = arm.flange_pose(s);
    EXPECT_LT((back.translation() - flange.translation()).norm(), 1e-6);
    EXPECT_LT(orientation_error(back, flange), 1e-6);
    took_given = took_given || std::abs(s[5] - 0.25) < 1e-12;
  }
  EXPECT_TRUE(took_given);
}

TEST(Ur5, UnreachablePosesHaveNoSolution) {
  const Ur5 arm;
  Eigen::Isometry3d far = Eigen::Isometry3d::Identity();
  far.translation() << 1.2, 0.3, 0.2;
  EXPECT_TRUE(arm.inverse(far).empty());
  // The wrist centre inside the d4 cylinder about joint 1 cannot be reached by any shoulder angle.
  Eigen::Isometry3d inside = Eigen::Isometry3d::Identity();
  inside.translation() << 0.02, 0.01, 0.3 + arm.config().geometry.d6;
  EXPECT_TRUE(arm.inverse(inside).empty());
}

TEST(Ur5, TopDownPoseFacesTheFloor) {
  const Eigen::Isometry3d pose = top_down_tool_pose({0.1, 0.5, -0.2}, 0.4);
  EXPECT_NEAR(pose.linear().col(2).z(), -1.0, 1e-15);
  EXPECT_NEAR(tool_yaw(pose), 0.4, 1e-15);
  EXPECT_NEAR(pose.linear().determinant(), 1.0, 1e-15);
}

TEST(Ur5, RejectsDegenerateGeometry) {
  Ur5Config config;
  config.geometry.a3 = 0.0;
  EXPECT_THROW(Ur5{config}, std::invalid_argument);
  config = {};
  config.max_reach = 0.0;
  EXPECT_THROW(Ur5{config}, std::invalid_argument);
}

TEST(JointLimits, Table10AcceptsItsInteriorAndRejectsEachJointOutside) {
  const JointLimits limits = JointLimits::picker_table10();
  const JointVector inside{-90 * kDeg, -70 * kDeg, 90 * kDeg, -20 * kDeg, -90 * kDeg, 0.0};
  EXPECT_FALSE(first_violation(inside, limits));
  const JointVector outside_values{-176 * kDeg, 1 * kDeg, 59 * kDeg, 1 * kDeg, 91 * kDeg, 0.01};
  for (int j = 0; j < kJointCount; ++j) {
    JointVector q = inside;
    q[static_cast<std::size_t>(j)] = outside_values[static_cast<std::size_t>(j)];
    const auto violation = first_violation(q, limits);
    ASSERT_TRUE(violation) << "joint " << j + 1;
    EXPECT_EQ(violation->joint, j + 1);
    EXPECT_NE(violation->describe().find("joint " + std::to_string(j + 1)), std::string::npos);
  }
}

TEST(JointLimits, ConstraintCNarrowsTheElbow) {
  JointVector q{-90 * kDeg, -70 * kDeg, 110 * kDeg, -40 * kDeg, -90 * kDeg, 0.0};
  EXPECT_FALSE(first_violation(q, JointLimits::picker_table10(false)));
  const auto violation = first_violation(q, JointLimits::picker_table10(true));
  ASSERT_TRUE(violation);
  EXPECT_EQ(violation->joint, 3);
}

TEST(JointLimits, FitToLimitsTurnsWholeTurns) {
  const JointLimits limits = JointLimits::picker_table10();
  const JointVector reference{-90 * kDeg, -70 * kDeg, 90 * kDeg, -20 * kDeg, -200 * kDeg, 0.0};
  // θ5 at 170° is outside θ5 <= 90°, but the same joint at -190° is inside.
  const JointVector q{-90 * kDeg, -70 * kDeg, 90 * kDeg, -20 * kDeg, 170 * kDeg, 0.0};
  const auto fitted = fit_to_limits(q, reference, limits);
  ASSERT_TRUE(fitted);
  EXPECT_NEAR((*fitted)[4], -190 * kDeg, 1e-12);
  // θ1 at 100° has no alias in [-175°, 60°].
  JointVector no_alias = q;
  no_alias[0] = 100 * kDeg;
  EXPECT_FALSE(fit_to_limits(no_alias, reference, limits));
}

TEST(JointLimits, ChooseNearestTakesTheClosestSolutionInside) {
  const JointLimits limits = JointLimits::picker_table10();
  const JointVector current{-90 * kDeg, -70 * kDeg, 90 * kDeg, -20 * kDeg, -90 * kDeg, 0.0};
  const JointVector near{-85 * kDeg, -70 * kDeg, 90 * kDeg, -20 * kDeg, -90 * kDeg, 0.0};
  const JointVector farther{-40 * kDeg, -70 * kDeg, 90 * kDeg, -20 * kDeg, -90 * kDeg, 0.0};
  const JointVector nearest_but_outside{-90 * kDeg, -70 * kDeg, 90 * kDeg, 2 * kDeg, -90 * kDeg, 0.0};
  const IkChoice choice = choose_nearest({farther, nearest_but_outside, near}, current, limits);
  ASSERT_TRUE(choice.joints);
  EXPECT_NEAR((*choice.joints)[0], near[0], 1e-12);

  const IkChoice none = choose_nearest({nearest_but_outside}, current, limits);
  EXPECT_FALSE(none.joints);
  ASSERT_TRUE(none.nearest_violation);
  EXPECT_EQ(none.nearest_violation->joint, 4);
}

TEST(JointSpeed, MoveTimeIsATrapezoidOfTheLeadingJoint) {
  const JointSpeedLimits limits;  // 1.05 rad/s, 1.4 rad/s²
  const JointVector from{0, 0, 0, 0, 0, 0};
  const JointVector quarter_turn{kPi / 2.0, 0.2, 0, 0, 0, 0};
  EXPECT_NEAR(joint_move_time(from, quarter_turn, limits), (kPi / 2.0) / 1.05 + 1.05 / 1.4, 1e-12);
  // Too short to reach the working speed: a triangle.
  const JointVector small{0.1, 0, 0, 0, 0, 0};
  EXPECT_NEAR(joint_move_time(from, small, limits), 2.0 * std::sqrt(0.1 / 1.4), 1e-12);
  EXPECT_EQ(joint_move_time(from, from, limits), 0.0);
  // The full speed of 180°/s is faster than the working speed.
  JointSpeedLimits full = limits;
  full.working_speed = full.max_speed;
  EXPECT_LT(joint_move_time(from, quarter_turn, full), joint_move_time(from, quarter_turn, limits));
}

TEST(JointSpeed, WorkingSpeedAboveTheUr5sMaximumIsAConfigurationError) {
  JointSpeedLimits limits;
  limits.working_speed = 200.0 * kDeg;
  EXPECT_THROW(limits.validate(), std::invalid_argument);
  limits = {};
  limits.acceleration = 0.0;
  EXPECT_THROW(limits.validate(), std::invalid_argument);
  EXPECT_NO_THROW(JointSpeedLimits{}.validate());
}
