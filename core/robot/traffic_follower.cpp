#include "robot/traffic_follower.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleet::robot {

TrafficPermit permit_of(model::TrafficGrant grant) {
  TrafficPermit permit;
  permit.version = grant.version;
  permit.granted_index = grant.granted_index;
  permit.granted_distance = grant.granted_distance;
  permit.blocked_by = std::move(grant.blocked_by);
  if (grant.status == "AREA_CLEAR") permit.area = TrafficPermit::Area::kClear;
  if (grant.status == "AREA_WAITING") permit.area = TrafficPermit::Area::kWaiting;
  if (!grant.instruction.empty()) {
    permit.route = std::move(grant.route);
    permit.siding = grant.instruction == "SIDING";
  }
  return permit;
}

using geometry::Vec2;

namespace {
std::vector<double> cumulative_lengths(const std::vector<Vec2>& points) {
  std::vector<double> cum(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) cum[i] = cum[i - 1] + geometry::distance(points[i - 1], points[i]);
  return cum;
}

/// Metres along `path` (arc lengths `cum`) of its cusps, where it turns back on itself (a route
/// that backs up a few places and comes back): the path follower's legs end there.
std::vector<double> cusp_lengths(const std::vector<Vec2>& path, const std::vector<double>& cum) {
  constexpr double kCuspAngle = 2.5;  // rad, as the path follower splits legs
  std::vector<double> cusps;
  std::size_t before = 0;
  for (std::size_t i = 1; i + 1 < path.size(); ++i) {
    if (cum[i] - cum[before] < 1e-6) continue;
    std::size_t after = i + 1;
    while (after + 1 < path.size() && cum[after] - cum[i] < 1e-6) ++after;
    const Vec2 in = path[i] - path[before];
    const Vec2 out = path[after] - path[i];
    if (geometry::dot(out, out) > 0.0 &&
        std::abs(std::atan2(geometry::cross(in, out), geometry::dot(in, out))) > kCuspAngle) {
      cusps.push_back(cum[i]);
    }
    before = i;
  }
  return cusps;
}
}  // namespace

std::uint64_t first_route_version(std::chrono::system_clock::time_point now) {
  const auto unix_s = std::chrono::duration_cast<std::chrono::seconds>(now.time_since_epoch()).count();
  return static_cast<std::uint64_t>(std::max<std::int64_t>(0, unix_s - 1'700'000'000)) * 16;
}

std::uint64_t next_own_route_version(std::uint64_t current) {
  return (current + 2) & ~std::uint64_t{1};
}

TrafficFollower::TrafficFollower(TrafficFollowerParams params)
    : TrafficFollower(params, first_route_version(std::chrono::system_clock::now())) {}

TrafficFollower::TrafficFollower(TrafficFollowerParams params, std::uint64_t first_version)
    : params_(params), version_(first_version) {}

void TrafficFollower::adopt_plan(const planning::Route& route) {
  path_ = route.points;
  path_cum_ = cumulative_lengths(path_);
  path_cusps_ = cusp_lengths(path_, path_cum_);
  path_s_ = 0.0;
  in_siding_ = false;
  siding_held_since_ = -1.0;
  road_points_ = route.road.point_ids;
  road_cum_ = cumulative_lengths(route.road.points);
  road_start_ = 0.0;
  goal_leg_.clear();
  goal_point_ = road_points_.empty() ? -1 : road_points_.back();
  if (road_points_.empty()) return;
  // The road part starts where the path first reaches the first road point; the rest of the path
  // after the last road point is the leg off the road to the goal, kept for re-routes.
  const Vec2 first = route.road.points.front();
  std::size_t first_index = 0;
  while (first_index + 1 < path_.size() && geometry::distance(path_[first_index], first) > 1e-9) ++first_index;
  road_start_ = path_cum_[first_index];
  // Found by its position, not counted from the first: the path holds each point once, the road
  // plan repeats the points where its edges join.
  const Vec2 last = route.road.points.back();
  std::size_t last_index = path_.size() - 1;
  while (last_index > first_index && geometry::distance(path_[last_index], last) > 1e-9) --last_index;
  goal_leg_.assign(path_.begin() + static_cast<std::ptrdiff_t>(last_index) + 1, path_.end());
  version_ = next_own_route_version(version_);
}

void TrafficFollower::adopt_route(const TrafficPermit& permit, const map::RoadGraph& graph, Vec2 here) {
  // Compared with the own plan's last point, not the route being driven: coming back from a
  // siding, that route is the siding's, and the robot still has to leave the road at the goal.
  const bool to_goal = !permit.siding && goal_point_ >= 0 && permit.route.back() == goal_point_;
  std::vector<Vec2> road;
  for (int id : permit.route)
    road.push_back({graph.points[static_cast<std::size_t>(id)].x, graph.points[static_cast<std::size_t>(id)].y});
  // A route handed over while the robot stood short of its grant starts at the route point at or
  // behind it: the path joins the route at the first point ahead, so the robot does not turn
  // round (sweeping its body into whoever stopped it) to touch a point it has passed. A route that
  // leads back the way the robot came still starts at its first point.
  std::size_t first = 0;
  while (first + 1 < road.size()) {
    const Vec2 ab = road[first + 1] - road[first];
    const double len2 = geometry::dot(ab, ab);
    const double along = len2 > 0.0 ? geometry::dot(here - road[first], ab) / len2 : 1.0;
    if (along <= 0.0) break;
    ++first;
    if (along < 1.0) break;
  }
  road_cum_ = cumulative_lengths(road);
  path_.assign(1, here);
  path_.insert(path_.end(), road.begin() + static_cast<std::ptrdiff_t>(first), road.end());
  // Where road point `first` sits on the path, less its distance along the road: progress along
  // the road is then path position - road_start_, as for a path through every road point.
  road_start_ = geometry::distance(here, road[first]) - road_cum_[first];
  if (to_goal) path_.insert(path_.end(), goal_leg_.begin(), goal_leg_.end());
  path_cum_ = cumulative_lengths(path_);
  path_cusps_ = cusp_lengths(path_, path_cum_);
  path_s_ = 0.0;
  road_points_ = permit.route;
  version_ = permit.version;
  in_siding_ = permit.siding;
  siding_held_since_ = -1.0;
}

void TrafficFollower::leave_road() {
  path_.clear();
  path_cum_.clear();
  path_cusps_.clear();
  road_points_.clear();  // parked beside the road: it holds no road any more
  road_cum_.clear();
}

void TrafficFollower::forget_route() {
  road_points_.clear();
  road_cum_.clear();
  pending_route_.reset();
  permit_ = {};
}

bool TrafficFollower::grant(const TrafficPermit& permit) {
  if (!params_.traffic) return false;
  bool replan = false;
  if (!permit.route.empty() && permit.version > version_ && !pending_route_) {
    pending_route_ = permit;
    replan = true;
  }
  if (!pending_route_) permit_ = permit;
  return replan;
}

std::optional<TrafficPermit> TrafficFollower::take_route() {
  std::optional<TrafficPermit> out = std::move(pending_route_);
  pending_route_.reset();
  return out;
}

double TrafficFollower::path_position(Vec2 here, std::optional<ControllerLeg> leg) const {
  // The projection onto the path near where the robot was last found: a path may pass close to
  // itself, and progress must not jump. A path that backs up and comes back runs over the same
  // ground twice: the robot is on the leg between the last cusp it reached and the next one, as
  // its controller says (it ends a leg within its own tolerance, and may skip a short first one).
  constexpr double kCuspReached = 0.03;  // metres: without the controller's word
  constexpr double kSameLength = 1e-6;   // metres
  constexpr double kLost = 0.15;         // metres off the stretch searched
  if (path_.size() < 2) return 0.0;
  const bool told = leg && std::abs(leg->path_length - path_cum_.back()) < kSameLength;
  double leg_from = 0.0;
  double leg_to = std::numeric_limits<double>::infinity();
  for (const double cusp : path_cusps_) {
    if (told ? cusp <= leg->leg_start_s + kSameLength : cusp <= path_s_ + kCuspReached) {
      leg_from = cusp;
    } else {
      leg_to = cusp;
      break;
    }
  }
  const double from_s = std::max(path_s_, leg_from);
  double best_d = std::numeric_limits<double>::infinity();
  double best_s = from_s;
  // Takes the point of segment i nearest the robot when it is nearer than the best so far, no
  // less than `floor` metres along the path.
  const auto consider = [&](std::size_t i, double floor) {
    const Vec2 a = path_[i];
    const Vec2 ab = path_[i + 1] - a;
    const double len2 = geometry::dot(ab, ab);
    const double u = len2 > 0.0 ? std::clamp(geometry::dot(here - a, ab) / len2, 0.0, 1.0) : 0.0;
    const double d = geometry::distance(here, a + u * ab);
    if (d < best_d) {
      best_d = d;
      best_s = std::max(floor, path_cum_[i] + u * std::sqrt(len2));
    }
  };
  for (std::size_t i = 0; i + 1 < path_.size(); ++i) {
    if (path_cum_[i + 1] < from_s - 0.05 || path_cum_[i] < leg_from - 1e-9) continue;
    if (path_cum_[i] > from_s + 0.30 || path_cum_[i + 1] > leg_to + 1e-9) break;
    consider(i, -std::numeric_limits<double>::infinity());
  }
  if (best_d > kLost) {
    // Lost: far from the stretch where it was last found (a leg its controller skipped, ended
    // early, or that no one said it had left). The nearest point of the path ahead of that
    // finds it again, so the room left in its grant shrinks as it drives.
    for (std::size_t i = 0; i + 1 < path_.size(); ++i) {
      if (path_cum_[i + 1] >= path_s_) consider(i, path_s_);
    }
  }
  return best_s;
}

std::optional<std::size_t> TrafficFollower::segment_on_leg() const {
  if (!params_.traffic || path_cusps_.empty() || path_.size() < 2) return std::nullopt;
  std::size_t segment = 0;
  while (segment + 2 < path_.size() && path_cum_[segment + 1] <= path_s_) ++segment;
  return segment;
}

std::optional<double> TrafficFollower::granted_end() const {
  if (!params_.traffic || road_points_.empty() || path_.size() < 2) return std::numeric_limits<double>::infinity();
  if (permit_.version != version_ || permit_.granted_index < 0) return std::nullopt;
  const bool whole_route = permit_.granted_index + 1 >= static_cast<int>(road_points_.size());
  if (whole_route && !in_siding_) return std::numeric_limits<double>::infinity();
  double allowed = road_start_ + permit_.granted_distance;
  // On a siding, stop just short of its end: the follower would take the end for the goal.
  if (in_siding_) allowed = std::min(allowed, road_start_ + road_cum_.back() - params_.siding_end_margin);
  return allowed;
}

double TrafficFollower::room(Vec2 here, std::optional<ControllerLeg> leg) {
  if (!params_.traffic || road_points_.empty() || path_.size() < 2) return std::numeric_limits<double>::infinity();
  path_s_ = path_position(here, leg);
  const std::optional<double> end = granted_end();
  // No grant for this route yet: stand still, not even turning on the spot; beside a lane a turn
  // sweeps the footprint into it. The manager admits the robot once its entry is free.
  if (!end) return -path_s_ - 1e-9;
  if (std::isinf(*end)) return *end;
  if (params_.wait_off_road_for_room && permit_.granted_index == 0 && path_s_ < road_start_) return -path_s_ - 1e-9;
  return *end - path_s_;
}

bool TrafficFollower::siding_timed_out(double t, bool held) {
  // Counted from the first hold on this siding, not reset when a hold flickers at its end.
  if (in_siding_ && held && siding_held_since_ < 0.0) siding_held_since_ = t;
  if (in_siding_ && siding_held_since_ >= 0.0 && t - siding_held_since_ > params_.siding_timeout && !pending_route_) {
    in_siding_ = false;
    return true;
  }
  return false;
}

TrafficRoute TrafficFollower::route() const {
  TrafficRoute r;
  r.version = version_;
  r.points = road_points_;
  if (!road_points_.empty()) r.progress = std::clamp(path_s_ - road_start_, 0.0, road_cum_.back());
  return r;
}

}  // namespace fleet::robot
