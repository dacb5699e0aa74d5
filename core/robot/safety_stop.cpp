#include "robot/safety_stop.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "planning/dynamic_grid.hpp"

namespace fleet::robot {

using geometry::Pose2;
using geometry::Vec2;

namespace {

// A safety stop for another robot's body is reported to the traffic manager once it lasted this
// long (sim seconds) with this robot within stop_moved of where it began: following a robot that
// stops briefly is no wait worth a re-route. A stop lapses after kStopGap without the check stopping.
constexpr double kReportStopAfter = 3.0;
constexpr double kStopGap = 1.0;

/// Distance from `p` to the footprint standing at `pose`, 0 inside.
double footprint_distance(const Pose2& pose, const geometry::Footprint& fp, Vec2 p) {
  const Vec2 b = geometry::map_to_body(pose, p);
  return std::hypot(std::max(std::abs(b.x) - fp.length / 2.0, 0.0), std::max(std::abs(b.y) - fp.width / 2.0, 0.0));
}

/// The radius of the smallest circle about `centre` that holds `polygon`.
double reach_of(const geometry::Polygon& polygon, Vec2 centre) {
  double r = 0.0;
  for (const Vec2& v : polygon) r = std::max(r, geometry::distance(v, centre));
  return r;
}

}  // namespace

void SafetyStop::take_scan(const planning::LidarScan& scan) {
  returns_.clear();
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!(r < params_.scan_range)) continue;
    const double a = scan.pose.yaw + scan.angle_min + static_cast<double>(i) * scan.angle_increment;
    returns_.push_back({scan.pose.x + r * std::cos(a), scan.pose.y + r * std::sin(a)});
  }
}

control::BodyTwist SafetyStop::safe(const control::BodyTwist& cmd, const Pose2& estimate,
                                    const std::vector<Neighbour>& neighbours) const {
  // In every state and every manoeuvre (backing out of a drop too): a command that would bring
  // this footprint within `safety_gap` of another robot within the horizon, and closer than it is
  // now, becomes a stop. Moving apart stays allowed, so two robots that met can always separate.
  if (cmd == control::BodyTwist{} || !moves_too_close(cmd, estimate, neighbours)) return cmd;
  // Refused close beside a body (a turn on the spot would swing a corner into it): the mecanum
  // base steps straight away from the nearest lidar return, slowly, when that step is safe, so
  // the robot makes room for the turn instead of standing there for good.
  const double kEscapeWithin = params_.escape_within;  // metres: only this close to a body
  const double kEscapeSpeed = params_.escape_speed;    // m/s
  const Vec2* nearest = nullptr;
  double nearest_gap = kEscapeWithin;
  for (const Vec2& p : returns_) {
    const double gap = footprint_distance(estimate, footprint_, p);
    if (gap < nearest_gap) {
      nearest_gap = gap;
      nearest = &p;
    }
  }
  if (nearest == nullptr) return {};
  const Vec2 away = geometry::map_to_body(estimate, *nearest);
  const double norm = std::hypot(away.x, away.y);
  if (norm < 1e-6) return {};
  const control::BodyTwist escape{-kEscapeSpeed * away.x / norm, -kEscapeSpeed * away.y / norm, 0.0};
  return moves_too_close(escape, estimate, neighbours) ? control::BodyTwist{} : escape;
}

bool SafetyStop::moves_too_close(const control::BodyTwist& cmd, const Pose2& estimate,
                                 const std::vector<Neighbour>& neighbours) const {
  // The footprint is swept over the horizon (passing a corner, the closest approach lies inside
  // it) and checked against two views of the others: the poses they publish (grown by what they
  // may have moved since), and the lidar's own returns, which a bias of this robot's estimate
  // does not move.
  constexpr double kHorizon = 0.4;  // sim seconds of the current command looked ahead
  constexpr int kSweepSteps = 4;
  if (neighbours.empty() && returns_.empty()) return false;
  std::array<Pose2, kSweepSteps> ahead;
  std::array<geometry::Polygon, kSweepSteps> mine_ahead;
  for (int k = 0; k < kSweepSteps; ++k) {
    ahead[k] = control::integrate_twist(estimate, cmd, kHorizon * (k + 1) / kSweepSteps);
    mine_ahead[k] = geometry::footprint_polygon(ahead[k], footprint_);
  }
  const auto mine_now = geometry::footprint_polygon(estimate, footprint_);
  // A body whose bounding circle stays further than the safety gap from every swept pose's
  // bounding circle cannot come within the gap: most of the others, most of the lidar returns.
  const Vec2 centre = estimate.position();
  double swept = 0.0;
  for (const Pose2& pose : ahead) swept = std::max(swept, geometry::distance(centre, pose.position()));
  const double body = std::max(reach_of(mine_now, centre), std::hypot(footprint_.length / 2.0, footprint_.width / 2.0));
  const double reach = body + swept + params_.safety_gap;
  for (const auto& n : neighbours) {
    const double moved =
        planning::distance_since_seen(n.speed, n.age, params_.stale_after, params_.neighbour_max_speed);
    const auto theirs = geometry::footprint_polygon(n.pose, n.footprint, std::min(moved, 1.0));
    if (geometry::distance(centre, n.pose.position()) > reach + reach_of(theirs, n.pose.position())) continue;
    const double gap_now = geometry::convex_polygons_distance(mine_now, theirs);
    for (const auto& mine : mine_ahead) {
      const double gap = geometry::convex_polygons_distance(mine, theirs);
      if (gap < params_.safety_gap && gap < gap_now) return true;
    }
  }
  for (const Vec2& p : returns_) {
    if (geometry::distance(centre, p) > reach) continue;
    const double gap_now = footprint_distance(estimate, footprint_, p);
    for (const Pose2& pose : ahead) {
      const double gap = footprint_distance(pose, footprint_, p);
      if (gap < params_.safety_gap && gap < gap_now) return true;
    }
  }
  return false;
}

std::string SafetyStop::robot_within(const Pose2& pose, const std::vector<Neighbour>& neighbours, double within) const {
  std::string nearest;
  double nearest_gap = std::numeric_limits<double>::infinity();
  for (const auto& n : neighbours) {
    const double gap = geometry::convex_polygons_distance(geometry::footprint_polygon(pose, footprint_),
                                                          geometry::footprint_polygon(n.pose, n.footprint));
    if (gap < nearest_gap) {
      nearest_gap = gap;
      nearest = n.robot_id;
    }
  }
  return std::isfinite(nearest_gap) && nearest_gap < within ? nearest : std::string{};
}

bool SafetyStop::Stop::current(double t, Vec2 here, double moved) const {
  return !robot_id.empty() && t - last_seen <= kStopGap && geometry::distance(here, where) <= moved;
}

void SafetyStop::note(double t, Vec2 here, const std::string& robot_id) {
  if (robot_id.empty()) return;
  if (robot_id != stop_.robot_id || !stop_.current(t, here, params_.stop_moved)) stop_ = {robot_id, t, here, t};
  stop_.last_seen = t;
}

std::vector<std::string> SafetyStop::stopped_for(double t, Vec2 here) const {
  if (stop_.current(t, here, params_.stop_moved) && t - stop_.since >= kReportStopAfter) return {stop_.robot_id};
  return {};
}

}  // namespace fleet::robot
