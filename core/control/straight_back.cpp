#include "control/straight_back.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::control {

namespace {

/// The rear axle's position from the goal in the goal's frame: x along its heading, y to its left.
geometry::Vec2 from_goal(const geometry::Pose2& goal, const geometry::Pose2& rear) {
  const double dx = rear.x - goal.x, dy = rear.y - goal.y;
  const double c = std::cos(goal.yaw), s = std::sin(goal.yaw);
  return {c * dx + s * dy, -s * dx + c * dy};
}

}  // namespace

StraightBack::StraightBack(const geometry::Pose2& goal, StraightBackParams params, double wheelbase, bool forward)
    : goal_(goal), forward_(forward), params_(params), wheelbase_(wheelbase) {}

double StraightBack::left(const geometry::Pose2& rear) const {
  const double x = from_goal(goal_, rear).x;
  return forward_ ? -x : x;
}

sim::TricycleCommand StraightBack::update(const geometry::Pose2& rear, double dt) {
  const geometry::Vec2 off = from_goal(goal_, rear);
  const double to_go = left(rear);
  if (done_ || to_go <= params_.tolerance) {
    done_ = true;
    speed_ = 0.0;
    return {0.0, 0.0};
  }
  // Trapezoidal: up at the acceleration, down so that it stands at the goal.
  const double stopping = std::sqrt(2.0 * params_.acceleration * to_go);
  speed_ = std::min({params_.max_speed, stopping, speed_ + params_.acceleration * dt});
  speed_ = std::max(speed_, 0.02);  // creeps the last millimetres
  // Backwards the lateral error y changes at -v sin(heading error): turning the heading towards
  // +y when the axle is off to the left brings it back onto the line; forwards, away from it.
  const double heading_error = geometry::angle_diff(rear.yaw, goal_.yaw);
  const double gain = forward_ ? params_.forward_lateral_gain : params_.lateral_gain;
  const double towards = std::asin(std::clamp(gain * off.y, -0.5, 0.5));
  const double wanted = forward_ ? -towards : towards;
  // The wheel kept within max_steer: a yaw rate beyond what the speed allows would pivot the body
  // on the spot and swing it past the line as it speeds up.
  const double most = speed_ * std::tan(params_.max_steer) / wheelbase_;
  const double yaw_rate = std::clamp(params_.heading_gain * (wanted - heading_error), -most, most);
  return sim::inverse_kinematics({forward_ ? speed_ : -speed_, yaw_rate}, wheelbase_);
}

bool straight_behind(const geometry::Pose2& rear, const geometry::Pose2& goal, double max_distance, double max_offset,
                     double max_yaw) {
  const geometry::Vec2 off = from_goal(goal, rear);
  return off.x >= 0.05 && off.x <= max_distance && std::abs(off.y) <= max_offset &&
         std::abs(geometry::angle_diff(rear.yaw, goal.yaw)) <= max_yaw;
}

bool straight_ahead(const geometry::Pose2& rear, const geometry::Pose2& goal, double max_distance, double max_offset,
                    double max_yaw) {
  const geometry::Vec2 off = from_goal(goal, rear);
  return -off.x >= 0.05 && -off.x <= max_distance && std::abs(off.y) <= max_offset &&
         std::abs(geometry::angle_diff(rear.yaw, goal.yaw)) <= max_yaw;
}

bool goal_ahead(const geometry::Pose2& rear, const geometry::Pose2& goal) {
  return from_goal(goal, rear).x < 0.0;
}

}  // namespace fleet::control
