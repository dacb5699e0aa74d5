#include "control/path_follower.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace fleet::control {

using geometry::angle_diff;
using geometry::normalize_angle;
using geometry::Pose2;
using geometry::Vec2;

namespace {

// How far ahead of the last projection the follower looks for the robot's new projection. Bounded
// so that a loop whose end passes near its start is not short-cut to the end.
constexpr double kProjectionWindow = 0.5;  // metres
// A turn sharper than this between consecutive segments is a cusp (about 145 degrees).
constexpr double kCuspAngle = 2.5;  // rad
// A grant must reach this far past a cusp for the next leg to start: more than the robot moves
// in a step, since the grant is counted from where it stood a step before.
constexpr double kPastCusp = 0.02;  // metres
// A final heading this far from the last segment's direction or further points back along it.
constexpr double kFacingBack = 2.36;  // rad, 135 degrees
// Segments within this of the last one's direction belong to the same straight stretch.
constexpr double kStraight = 0.09;  // rad, 5 degrees

double clamp_abs(double v, double limit) {
  return std::clamp(v, -limit, limit);
}

double step_towards(double from, double to, double max_change) {
  return from + std::clamp(to - from, -max_change, max_change);
}

}  // namespace

FollowerParams FollowerParams::regulated() {
  FollowerParams p;
  p.smooth_lookahead = true;
  p.regulate_curvature = true;
  p.regulate_obstacles = true;
  p.limit_acceleration = true;
  p.shortest_first_leg = 0.25;
  p.back_in_up_to = 0.5;
  p.reverse_legs_up_to = 0.4;
  return p;
}

const char* to_string(FollowerStatus status) {
  switch (status) {
    case FollowerStatus::kIdle:
      return "idle";
    case FollowerStatus::kTracking:
      return "tracking";
    case FollowerStatus::kAligning:
      return "aligning";
    case FollowerStatus::kArrived:
      return "arrived";
  }
  return "unknown";
}

double speed_law(double omega, double v_max, double omega_max) {
  // [Forklift thesis, eq. 6.2], normalised so that v = v_max at omega = 0 and v = 0 at omega_max.
  if (omega_max <= 0.0) return 0.0;
  const double ratio = std::min(std::abs(omega) / omega_max, 1.0);
  return v_max * (1.0 - ratio);
}

PathFollower::PathFollower(FollowerParams params) : params_(params) {
  if (!(params_.v_max > 0.0)) throw std::invalid_argument("follower: v_max must be > 0");
  if (!(params_.omega_max > 0.0)) throw std::invalid_argument("follower: omega_max must be > 0");
  if (!(params_.lookahead > 0.0)) throw std::invalid_argument("follower: lookahead must be > 0");
  if (params_.regulate_obstacles && !(params_.obstacle_slow_distance > params_.obstacle_stop_distance)) {
    throw std::invalid_argument("follower: obstacle_slow_distance must exceed obstacle_stop_distance");
  }
}

void PathFollower::reset_controller() {
  integral_ = 0.0;
  prev_beta_ = 0.0;
  have_prev_ = false;
  progress_ = 0;
  target_index_ = 0;
  leg_ = 0;
  debug_ = {};
}

void PathFollower::set_path(std::vector<Pose2> path, bool may_back_in) {
  if (path.empty()) throw std::invalid_argument("follower: empty path");
  // Drop repeated points: a zero-length segment has no direction.
  std::vector<Pose2> cleaned;
  cleaned.reserve(path.size());
  for (const Pose2& p : path) {
    if (!cleaned.empty() && geometry::distance(cleaned.back().position(), p.position()) < 1e-6) {
      cleaned.back().yaw = p.yaw;
      continue;
    }
    cleaned.push_back(p);
  }
  path_ = std::move(cleaned);
  cum_.assign(path_.size(), 0.0);
  for (std::size_t i = 1; i < path_.size(); ++i) {
    cum_[i] = cum_[i - 1] + geometry::distance(path_[i - 1].position(), path_[i].position());
  }
  pose_target_ = path_.size() == 1;
  // Split at cusps, where the path turns back on itself (a road-graph route that reverses along
  // a single-lane road): each leg is followed to its end before the next one starts.
  leg_ends_.clear();
  for (std::size_t i = 1; i + 1 < path_.size(); ++i) {
    const Vec2 in = path_[i].position() - path_[i - 1].position();
    const Vec2 out = path_[i + 1].position() - path_[i].position();
    const double turn = std::abs(std::atan2(geometry::cross(in, out), geometry::dot(in, out)));
    if (turn > kCuspAngle) leg_ends_.push_back(i);
  }
  leg_ends_.push_back(path_.size() - 1);
  backwards_leg_ = leg_ends_.size();
  leg_chosen_ = false;
  if (may_back_in && !pose_target_ && params_.back_in_up_to > 0.0) split_off_back_in();
  status_ = FollowerStatus::kTracking;
  reset_controller();
  // A leg short enough to reverse is driven: it may be a move traffic asked for (backing up out
  // of another robot's way), and driving it backwards turns nothing round.
  const double first_leg = cum_[leg_ends_.front()];
  if (leg_ends_.size() > 1 && first_leg < params_.shortest_first_leg && first_leg > params_.reverse_legs_up_to) {
    // The projection may overshoot a leg's start, so the robot joins the second leg from behind it.
    leg_ = 1;
    progress_ = leg_start();
    target_index_ = progress_;
  }
}

void PathFollower::split_off_back_in() {
  const std::size_t last = path_.size() - 1;
  const Vec2 along = path_[last].position() - path_[last - 1].position();
  const double direction = std::atan2(along.y, along.x);
  if (std::abs(angle_diff(path_[last].yaw, direction)) < kFacingBack) return;
  const std::size_t leg_begin = leg_ends_.size() > 1 ? leg_ends_[leg_ends_.size() - 2] : 0;
  std::size_t start = last - 1;
  while (start > leg_begin) {
    const Vec2 before = path_[start].position() - path_[start - 1].position();
    if (std::abs(angle_diff(std::atan2(before.y, before.x), direction)) > kStraight) break;
    --start;
  }
  if (cum_[last] - cum_[start] > params_.back_in_up_to) {
    // A long stretch: the turn comes back_in_up_to short of the end, on the stretch itself.
    const double s = cum_[last] - params_.back_in_up_to;
    std::size_t i = start;
    while (cum_[i + 1] <= s) ++i;
    const Vec2 turn_at = path_[i].position() +
                         ((s - cum_[i]) / (cum_[i + 1] - cum_[i])) * (path_[i + 1].position() - path_[i].position());
    if (s - cum_[i] > 1e-6) {
      path_.insert(path_.begin() + static_cast<std::ptrdiff_t>(i) + 1, Pose2{turn_at.x, turn_at.y, direction});
      cum_.insert(cum_.begin() + static_cast<std::ptrdiff_t>(i) + 1, s);
      ++i;
      ++leg_ends_.back();
    }
    start = i;
  }
  if (start > leg_begin) leg_ends_.insert(leg_ends_.end() - 1, start);
  backwards_leg_ = leg_ends_.size() - 1;
}

bool PathFollower::drives_backwards(const Pose2& pose) {
  if (leg_ == backwards_leg_) return true;
  if (!leg_chosen_ || chosen_leg_ != leg_) {
    chosen_leg_ = leg_;
    leg_chosen_ = true;
    const Vec2 to_end = path_[leg_end()].position() - pose.position();
    const double length = cum_[leg_end()] - cum_[leg_start()];
    leg_reversed_ = !pose_target_ && params_.reverse_legs_up_to > 0.0 && length <= params_.reverse_legs_up_to &&
                    geometry::dot(to_end, to_end) > 0.0 &&
                    std::abs(angle_diff(std::atan2(to_end.y, to_end.x), pose.yaw)) > kFacingBack;
  }
  return leg_reversed_;
}

void PathFollower::set_pose_target(const Pose2& target) {
  set_path({target});
}

void PathFollower::clear() {
  path_.clear();
  cum_.clear();
  pose_target_ = false;
  status_ = FollowerStatus::kIdle;
  last_cmd_ = {};
  reset_controller();
}

PathFollower::Projection PathFollower::project(Vec2 p) {
  Projection best;
  double best_d2 = std::numeric_limits<double>::infinity();
  const std::size_t last_seg = leg_end() - 1;
  // The window runs on from the end of the segment last projected onto: measured from its start,
  // a segment longer than the window (a route joined from where the robot stands) would hide the
  // next one, and the robot at its end would chase a target it stands on.
  const double s_limit = cum_[std::min(progress_ + 1, last_seg + 1)] + kProjectionWindow + params_.lookahead;
  for (std::size_t i = progress_; i <= last_seg; ++i) {
    if (i > progress_ && cum_[i] > s_limit) break;
    const Vec2 a = path_[i].position();
    const Vec2 b = path_[i + 1].position();
    const Vec2 ab = b - a;
    const double len2 = geometry::dot(ab, ab);
    double t = geometry::dot(p - a, ab) / len2;
    // Only the ends of the current leg may be overshot; inner segments clamp.
    const double t_lo = (i == leg_start()) ? -std::numeric_limits<double>::infinity() : 0.0;
    const double t_hi = (i == last_seg) ? std::numeric_limits<double>::infinity() : 1.0;
    t = std::clamp(t, t_lo, t_hi);
    const Vec2 q = a + t * ab;
    const double d2 = geometry::dot(p - q, p - q);
    if (d2 < best_d2 - 1e-12) {
      best_d2 = d2;
      const double len = std::sqrt(len2);
      best.segment = i;
      best.t = t;
      best.s = cum_[i] + t * len;
      best.cross = geometry::cross(ab, p - a) / len;
    }
  }
  progress_ = best.segment;
  return best;
}

Vec2 PathFollower::point_at(double s) const {
  // Beyond the end the path continues straight along its last segment, so the target never
  // collapses onto the robot as it arrives (Nav2 RPP interpolates past the goal the same way).
  const std::size_t end = leg_end();
  if (s >= cum_[end]) {
    const Vec2 a = path_[end - 1].position();
    const Vec2 b = path_[end].position();
    const Vec2 dir = (1.0 / geometry::distance(a, b)) * (b - a);
    return b + (s - cum_[end]) * dir;
  }
  if (s <= 0.0) return path_.front().position();
  const auto it = std::upper_bound(cum_.begin(), cum_.end(), s);
  const std::size_t i = static_cast<std::size_t>(it - cum_.begin()) - 1;
  const double t = (s - cum_[i]) / (cum_[i + 1] - cum_[i]);
  return path_[i].position() + t * (path_[i + 1].position() - path_[i].position());
}

Vec2 PathFollower::granted_target(double s, double granted) const {
  if (!(granted < params_.lookahead)) return point_at(s + params_.lookahead);
  // A robot may not drive past the end of its grant, so it steers for the path as far as that
  // and straight on beyond it: held before a bend, it keeps its heading and does not turn its
  // body on the spot over ground traffic has not given it.
  const double held = std::max(granted, 0.0);
  const Vec2 end = point_at(s + held);
  constexpr double kBack = 0.05;  // metres along the path that give the direction at the grant end
  Vec2 direction = end - point_at(std::max(s + held - kBack, 0.0));
  if (geometry::dot(direction, direction) < 1e-12) direction = point_at(s + held + kBack) - end;
  const double length = std::hypot(direction.x, direction.y);
  if (length < 1e-6) return point_at(s + params_.lookahead);
  return end + ((params_.lookahead - held) / length) * direction;
}

Vec2 PathFollower::seed_target(Vec2 p, std::size_t& index) {
  // The first path point past the robot that is at least the minimum
  // distance away [Forklift thesis, section 6.1]. The index never goes back, so the target only ever moves forward.
  const std::size_t end = leg_end();
  std::size_t i = std::max(target_index_, progress_ + 1);
  while (i < end && geometry::distance(p, path_[i].position()) < params_.lookahead) ++i;
  target_index_ = i;
  index = i;
  if (i == end && geometry::distance(p, path_[i].position()) < params_.lookahead) {
    return point_at(cum_[end] + params_.lookahead);
  }
  return path_[i].position();
}

BodyTwist PathFollower::limit_turn(BodyTwist cmd, double dt) {
  if (!params_.limit_acceleration || dt <= 0.0) return cmd;
  cmd.omega = step_towards(last_cmd_.omega, cmd.omega, params_.max_angular_accel * dt);
  // Whatever forward speed is left when the end is reached is taken off at the limit too.
  cmd.vx = step_towards(last_cmd_.vx, 0.0, params_.max_linear_accel * dt);
  return cmd;
}

BodyTwist PathFollower::step(const FollowerInput& in) {
  BodyTwist cmd;
  if (status_ == FollowerStatus::kIdle || status_ == FollowerStatus::kArrived || path_.empty()) {
    last_cmd_ = {};
    return cmd;
  }
  const Vec2 p = in.pose.position();
  const Pose2& goal = path_.back();

  if (status_ == FollowerStatus::kTracking) {
    Vec2 target;
    double remaining = 0.0;
    bool held_at_cusp = false;
    if (pose_target_) {
      target = goal.position();
      remaining = geometry::distance(p, target);
      debug_.cross_track = 0.0;
      debug_.target_index = 0;
    } else {
      Projection proj = project(p);
      remaining = cum_[leg_end()] - proj.s;
      const bool at_cusp = remaining <= params_.goal_tolerance && leg_ + 1 < leg_ends_.size();
      // A grant that ends at the cusp: the robot drives on up to the grant's end, as anywhere
      // else, and stays on this leg until the grant reaches on. Turned onto the next leg, it
      // would count as driving on past the grant's end.
      held_at_cusp = at_cusp && in.granted_distance <= remaining + kPastCusp;
      if (at_cusp && !held_at_cusp) {
        // At a cusp: the next leg starts here and points back the way the robot came. Its target
        // lies behind, so eq. 6.2 turns the robot in place before it drives on.
        progress_ = leg_end();
        target_index_ = progress_;
        ++leg_;
        have_prev_ = false;
        integral_ = 0.0;
        proj = project(p);
        remaining = cum_[leg_end()] - proj.s;
      }
      debug_.cross_track = proj.cross;
      if (params_.smooth_lookahead) {
        target = granted_target(proj.s, in.granted_distance);
        debug_.target_index = proj.segment;
      } else {
        target = seed_target(p, debug_.target_index);
      }
    }
    debug_.remaining = remaining;
    debug_.target = target;
    if (remaining <= params_.goal_tolerance && !held_at_cusp) {
      status_ = FollowerStatus::kAligning;
    } else {
      // Backing in, the rear leads: h is the heading of the rear, and the speed is negated below.
      const bool backwards = drives_backwards(in.pose);
      const double heading = backwards ? normalize_angle(in.pose.yaw + std::numbers::pi) : in.pose.yaw;
      const double last_vx = backwards ? -last_cmd_.vx : last_cmd_.vx;
      // beta = h - atan2(yd - y, xd - x) [Forklift thesis, eq. 6.3].
      const double beta = normalize_angle(heading - std::atan2(target.y - p.y, target.x - p.x));
      debug_.beta = beta;
      double derivative = 0.0;
      if (in.dt > 0.0) {
        if (have_prev_) derivative = angle_diff(beta, prev_beta_) / in.dt;
        integral_ = clamp_abs(integral_ + beta * in.dt, params_.integral_limit);
      }
      prev_beta_ = beta;
      have_prev_ = true;
      // beta > 0 means the heading is left of the target, so the turn is clockwise (negative).
      const double u = params_.kp * beta + params_.ki * integral_ + params_.kd * derivative;
      cmd.omega = clamp_abs(-u, params_.omega_max);
      if (params_.limit_acceleration && in.dt > 0.0) {
        cmd.omega = step_towards(last_cmd_.omega, cmd.omega, params_.max_angular_accel * in.dt);
      }
      // Slower the harder it turns; turns in place at omega_max [Forklift thesis, eq. 6.2].
      cmd.vx = speed_law(cmd.omega, params_.v_max, params_.omega_max);
      if (params_.regulate_curvature) {
        // Nav2 RPP: curvature of the arc through the target, kappa = 2 y / L^2 in the body frame.
        const Vec2 tb = geometry::map_to_body(in.pose, target);
        const double l2 = geometry::dot(tb, tb);
        const double kappa = l2 > 1e-9 ? 2.0 * tb.y / l2 : 0.0;
        const double radius = std::abs(kappa) > 1e-9 ? 1.0 / std::abs(kappa) : std::numeric_limits<double>::infinity();
        if (radius < params_.regulate_min_radius) {
          const double v = cmd.vx * radius / params_.regulate_min_radius;
          cmd.vx = std::min(cmd.vx, std::max(v, params_.regulated_min_speed));
        }
      }
      if (params_.regulate_obstacles) {
        const double d = in.obstacle_distance;
        if (d <= params_.obstacle_stop_distance) {
          cmd.vx = 0.0;
        } else if (d < params_.obstacle_slow_distance) {
          const double scale =
              (d - params_.obstacle_stop_distance) / (params_.obstacle_slow_distance - params_.obstacle_stop_distance);
          cmd.vx = std::min(cmd.vx, std::max(cmd.vx * scale, params_.regulated_min_speed));
        }
      }
      if (params_.limit_acceleration && in.dt > 0.0) {
        // v^2 = v_end^2 + 2 a' s: reaches the end at v_end, small enough to stop within one
        // step's allowance. a' is below the limit so the rate-limited speed can keep up with the
        // curve between steps instead of falling behind it.
        const double v_end = params_.max_linear_accel * in.dt;
        const double a_brake = 0.8 * params_.max_linear_accel;
        const double v_stop =
            std::sqrt(v_end * v_end + 2.0 * a_brake * std::max(remaining - params_.goal_tolerance, 0.0));
        cmd.vx = std::min(cmd.vx, v_stop);
        cmd.vx = step_towards(last_vx, cmd.vx, params_.max_linear_accel * in.dt);
      }
      if (backwards) cmd.vx = -cmd.vx;
      last_cmd_ = cmd;
      return cmd;
    }
  }

  // Aligning: the thesis's controller does not stop by itself; it is stopped once the heading
  // error to the final pose is near zero (Forklift thesis, section 6.1).
  const double dh = angle_diff(goal.yaw, in.pose.yaw);
  debug_.beta = -dh;
  if (std::abs(dh) <= params_.heading_tolerance) {
    status_ = FollowerStatus::kArrived;
    last_cmd_ = {};
    return {};
  }
  double omega = params_.rotate_gain * dh;
  if (std::abs(omega) < params_.rotate_omega_min) omega = std::copysign(params_.rotate_omega_min, dh);
  cmd.omega = clamp_abs(omega, params_.omega_max);
  cmd = limit_turn(cmd, in.dt);
  last_cmd_ = cmd;
  return cmd;
}

}  // namespace fleet::control
