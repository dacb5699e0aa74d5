#include "arm/ur5.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "geometry/pose.hpp"

namespace fleet::arm {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Twists of the UR geometry [Picker thesis, Table 1].
constexpr std::array<double, kJointCount> kAlpha{kPi / 2.0, 0.0, 0.0, kPi / 2.0, -kPi / 2.0, 0.0};

/// One link of standard (distal) DH: Rz(θ)·Tz(d)·Tx(a)·Rx(α). Table 1 lists distal parameters and
/// eq. 4.36-4.38 are their product; eq. 3.9 prints the proximal (Craig) form, which with Table 1
/// would describe a different arm.
Eigen::Isometry3d dh_link(double theta, double d, double a, double alpha) {
  const double ct = std::cos(theta);
  const double st = std::sin(theta);
  const double ca = std::cos(alpha);
  const double sa = std::sin(alpha);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0.0, sa, ca;
  t.translation() << a * ct, a * st, d;
  return t;
}

std::array<double, kJointCount> link_d(const Ur5Geometry& g) {
  return {g.d1, 0.0, 0.0, g.d4, g.d5, g.d6};
}
std::array<double, kJointCount> link_a(const Ur5Geometry& g) {
  return {0.0, g.a2, g.a3, 0.0, 0.0, 0.0};
}

/// The two shoulder angles that put the wrist centre `p5` in the plane of the upper arm and
/// forearm, offset d4 from it: p5 · z1 = d4 with z1 = (sin θ1, -cos θ1, 0).
std::vector<double> shoulder_angles(const Eigen::Vector3d& p5, double d4) {
  const double radius = std::hypot(p5.x(), p5.y());
  if (radius < std::abs(d4) - 1e-12 || radius == 0.0) return {};
  const double phi = std::atan2(p5.y(), p5.x());
  const double offset = std::asin(std::clamp(d4 / radius, -1.0, 1.0));
  return {phi + offset, phi + kPi - offset};
}

/// Sum of the amounts by which each joint misses its range.
double violation_amount(const JointVector& q, const JointLimits& limits) {
  double total = 0.0;
  for (int j = 0; j < kJointCount; ++j) {
    const JointRange& r = limits.ranges[static_cast<std::size_t>(j)];
    const double v = q[static_cast<std::size_t>(j)];
    total += std::max({0.0, r.lower - v, v - r.upper});
  }
  return total;
}

/// The whole-turn alias of `value` nearest its range, and among equals nearest `reference`.
double best_alias(double value, double reference, const JointRange& range) {
  double best = value;
  double best_miss = std::numeric_limits<double>::infinity();
  double best_distance = std::numeric_limits<double>::infinity();
  for (int turns = -2; turns <= 2; ++turns) {
    const double v = value + turns * kTwoPi;
    const double miss = std::max({0.0, range.lower - v, v - range.upper});
    const double distance = std::abs(v - reference);
    if (miss < best_miss - kLimitTolerance || (miss <= best_miss + kLimitTolerance && distance < best_distance)) {
      best = v;
      best_miss = miss;
      best_distance = distance;
    }
  }
  return best;
}

double joint_distance(const JointVector& a, const JointVector& b) {
  double sum = 0.0;
  for (std::size_t j = 0; j < a.size(); ++j) sum += (a[j] - b[j]) * (a[j] - b[j]);
  return std::sqrt(sum);
}

}  // namespace

JointLimits JointLimits::ur5_hardware() {
  JointLimits limits;
  for (auto& r : limits.ranges) r = {-kTwoPi, kTwoPi};
  return limits;
}

JointLimits JointLimits::picker_table10(bool constraint_c) {
  JointLimits limits;
  limits.ranges = {{
      {-175.0 * kDeg, 60.0 * kDeg},
      {-90.0 * kDeg, 0.0},
      {60.0 * kDeg, (constraint_c ? 100.0 : 135.0) * kDeg},
      {-100.0 * kDeg, 0.0},
      {-kTwoPi, 90.0 * kDeg},
      {0.0, 0.0},
  }};
  return limits;
}

std::string LimitViolation::describe() const {
  char text[128];
  std::snprintf(text, sizeof text, "joint %d at %.2f° outside [%.1f°, %.1f°]", joint, value / kDeg, range.lower / kDeg,
                range.upper / kDeg);
  return text;
}

std::optional<LimitViolation> first_violation(const JointVector& q, const JointLimits& limits) {
  for (int j = 0; j < kJointCount; ++j) {
    const JointRange& r = limits.ranges[static_cast<std::size_t>(j)];
    const double v = q[static_cast<std::size_t>(j)];
    if (v < r.lower - kLimitTolerance || v > r.upper + kLimitTolerance) return LimitViolation{j + 1, v, r};
  }
  return std::nullopt;
}

std::optional<JointVector> fit_to_limits(const JointVector& q, const JointVector& reference,
                                         const JointLimits& limits) {
  JointVector fitted{};
  for (std::size_t j = 0; j < q.size(); ++j) {
    fitted[j] = best_alias(q[j], reference[j], limits.ranges[j]);
  }
  if (first_violation(fitted, limits)) return std::nullopt;
  return fitted;
}

IkChoice choose_nearest(const std::vector<JointVector>& solutions, const JointVector& current,
                        const JointLimits& limits) {
  IkChoice choice;
  double best_distance = std::numeric_limits<double>::infinity();
  double least_miss = std::numeric_limits<double>::infinity();
  for (const JointVector& solution : solutions) {
    if (const auto fitted = fit_to_limits(solution, current, limits)) {
      const double distance = joint_distance(*fitted, current);
      if (distance < best_distance) {
        best_distance = distance;
        choice.joints = fitted;
      }
      continue;
    }
    // Keep the closest miss so that a refusal can say which joint is in the way.
    JointVector aliased{};
    for (std::size_t j = 0; j < solution.size(); ++j) {
      aliased[j] = best_alias(solution[j], current[j], limits.ranges[j]);
    }
    const double miss = violation_amount(aliased, limits);
    if (miss < least_miss) {
      least_miss = miss;
      choice.nearest_violation = first_violation(aliased, limits);
    }
  }
  if (choice.joints) choice.nearest_violation.reset();
  return choice;
}

void JointSpeedLimits::validate() const {
  auto require_positive = [](double value, const char* name) {
    if (!(value > 0.0)) {
      throw std::invalid_argument(std::string("JointSpeedLimits.") + name + " must be > 0, got " +
                                  std::to_string(value));
    }
  };
  require_positive(max_speed, "max_speed");
  require_positive(working_speed, "working_speed");
  require_positive(acceleration, "acceleration");
  if (working_speed > max_speed) {
    throw std::invalid_argument("JointSpeedLimits.working_speed " + std::to_string(working_speed) +
                                " rad/s exceeds max_speed " + std::to_string(max_speed) + " rad/s");
  }
}

double trapezoid_time(double distance, double speed, double acceleration) {
  if (distance <= 0.0) return 0.0;
  if (distance >= speed * speed / acceleration) return distance / speed + speed / acceleration;
  return 2.0 * std::sqrt(distance / acceleration);
}

double joint_move_time(const JointVector& from, const JointVector& to, const JointSpeedLimits& limits) {
  double longest = 0.0;
  for (std::size_t j = 0; j < from.size(); ++j) longest = std::max(longest, std::abs(to[j] - from[j]));
  return trapezoid_time(longest, limits.working_speed, limits.acceleration);
}

Ur5::Ur5(Ur5Config config) : config_(config) {
  const Ur5Geometry& g = config_.geometry;
  if (g.a2 == 0.0 || g.a3 == 0.0) throw std::invalid_argument("Ur5Geometry: a2 and a3 must be non-zero");
  if (!(g.d6 > 0.0)) throw std::invalid_argument("Ur5Geometry.d6 must be > 0, got " + std::to_string(g.d6));
  if (g.d4 < 0.0) throw std::invalid_argument("Ur5Geometry.d4 must be >= 0, got " + std::to_string(g.d4));
  if (!(config_.max_reach > 0.0)) {
    throw std::invalid_argument("Ur5Config.max_reach must be > 0, got " + std::to_string(config_.max_reach));
  }
}

std::array<Eigen::Isometry3d, kJointCount> Ur5::link_frames(const JointVector& q) const {
  const auto d = link_d(config_.geometry);
  const auto a = link_a(config_.geometry);
  std::array<Eigen::Isometry3d, kJointCount> frames;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    t = t * dh_link(q[i], d[i], a[i], kAlpha[i]);
    frames[i] = t;
  }
  return frames;
}

Eigen::Isometry3d Ur5::flange_pose(const JointVector& q) const {
  return link_frames(q).back();
}

Eigen::Isometry3d Ur5::tool_pose(const JointVector& q) const {
  return flange_pose(q) * config_.tool.flange_to_tool();
}

std::vector<JointVector> Ur5::inverse(const Eigen::Isometry3d& flange, double theta6_if_singular) const {
  const Ur5Geometry& g = config_.geometry;
  const Eigen::Matrix3d& r = flange.linear();
  const Eigen::Vector3d x6 = r.col(0);
  const Eigen::Vector3d y6 = r.col(1);
  const Eigen::Vector3d z6 = r.col(2);
  // Wrist centre (origin of frame 5): d6 back along the flange axis.
  const Eigen::Vector3d p5 = flange.translation() - g.d6 * z6;

  std::vector<JointVector> solutions;
  for (const double theta1 : shoulder_angles(p5, g.d4)) {
    // Joints 2-4 turn about z1; joint 5 tilts the flange axis out of their plane by θ5, so
    // z6 · z1 = cos θ5 and the flange's x and y seen along z1 give sin θ5 and θ6.
    const Eigen::Vector3d z1(std::sin(theta1), -std::cos(theta1), 0.0);
    const double c5 = z6.dot(z1);
    const double s5_magnitude = std::hypot(x6.dot(z1), y6.dot(z1));
    for (const double wrist : {1.0, -1.0}) {
      const double theta5 = std::atan2(wrist * s5_magnitude, c5);
      const double theta6 =
          s5_magnitude < 1e-10 ? theta6_if_singular : std::atan2(-wrist * y6.dot(z1), wrist * x6.dot(z1));
      // Strip joints 1, 5 and 6: what is left is the planar chain of joints 2-4 in frame 1.
      const Eigen::Isometry3d t14 =
          dh_link(theta1, g.d1, 0.0, kAlpha[0]).inverse() * flange *
          (dh_link(theta5, g.d5, 0.0, kAlpha[4]) * dh_link(theta6, g.d6, 0.0, kAlpha[5])).inverse();
      const double x = t14.translation().x();
      const double y = t14.translation().y();
      const double c3 = (x * x + y * y - g.a2 * g.a2 - g.a3 * g.a3) / (2.0 * g.a2 * g.a3);
      if (std::abs(c3) > 1.0 + 1e-12) continue;
      const double theta234 = std::atan2(t14.linear()(1, 0), t14.linear()(0, 0));
      for (const double elbow : {1.0, -1.0}) {
        const double theta3 = elbow * std::acos(std::clamp(c3, -1.0, 1.0));
        const double theta2 = std::atan2(y, x) - std::atan2(g.a3 * std::sin(theta3), g.a2 + g.a3 * std::cos(theta3));
        const double theta4 = theta234 - theta2 - theta3;
        solutions.push_back({geometry::normalize_angle(theta1), geometry::normalize_angle(theta2),
                             geometry::normalize_angle(theta3), geometry::normalize_angle(theta4),
                             geometry::normalize_angle(theta5), geometry::normalize_angle(theta6)});
      }
    }
  }
  return solutions;
}

std::vector<JointVector> Ur5::inverse_tool(const Eigen::Isometry3d& tool, double theta6_if_singular) const {
  return inverse(tool * config_.tool.flange_to_tool().inverse(), theta6_if_singular);
}

Eigen::Isometry3d ToolMount::flange_to_tool() const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  // Columns: the tool's x, y, z in the flange frame.
  t.linear() << 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0;
  t.translation() << 0.0, -below_axis, along_axis;
  return t;
}

Eigen::Isometry3d top_down_tool_pose(const Eigen::Vector3d& position, double yaw) {
  const Eigen::Vector3d x(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d z(0.0, 0.0, -1.0);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().col(0) = x;
  pose.linear().col(1) = z.cross(x);
  pose.linear().col(2) = z;
  pose.translation() = position;
  return pose;
}

double tool_yaw(const Eigen::Isometry3d& tool) {
  return std::atan2(tool.linear()(1, 0), tool.linear()(0, 0));
}

double orientation_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

}  // namespace fleet::arm
