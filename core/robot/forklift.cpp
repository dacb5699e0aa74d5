#include "robot/forklift.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

namespace fleet::robot {

using geometry::Pose2;
using geometry::Vec2;

namespace {

constexpr double kDynamicUpdatePeriod = 0.1;  // sim seconds between dynamic-grid rebuilds (10 Hz)
constexpr double kDetourAfter = 3.0;          // sim seconds blocked before a temporary obstacle goes in
constexpr int kClearChecks = 3;               // dynamic updates a temporary must be seen free
// A safety stop for another robot's body is reported to the traffic manager once it lasted this
// long (sim seconds) with this robot within stop_moved of where it began: following a robot that
// stops briefly is no wait worth a re-route. A stop lapses after kStopGap without the check stopping.
constexpr double kReportStopAfter = 3.0;
constexpr double kStopGap = 1.0;

planning::StaticGrid make_static_grid(const ForkliftConfig& c, const map::SiteMap& site) {
  return planning::StaticGrid({.resolution = c.grid_resolution}, site.site, site.graph.graph);
}

geometry::Polygon box_around(Vec2 c, double side) {
  const double h = side / 2.0;
  return {{c.x - h, c.y - h}, {c.x + h, c.y - h}, {c.x + h, c.y + h}, {c.x - h, c.y + h}};
}

}  // namespace

Forklift::Forklift(const ForkliftConfig& config, std::shared_ptr<const map::SiteMap> site, const Pose2& home,
                   std::uint64_t seed, std::uint64_t stream)
    : config_(config),
      site_(std::move(site)),
      sim_(config.sim, site_->site, home, seed, stream),
      camera_(
          [&] {
            perception::MarkerCameraParams cp = config.camera;
            cp.camera_x = config.task.geometry.camera_x;
            return cp;
          }(),
          seed * 7919 + stream),
      pallets_([&] {
        perception::PalletWorldParams wp = config.pallet_world;
        wp.carry_x = config.task.geometry.carry_x;
        wp.marker_offset = config.task.geometry.marker_offset;
        return wp;
      }()),
      executor_(config.task, home),
      static_grid_(make_static_grid(config, *site_)),
      dynamic_([&] {
        // No growth by our own size: clearance_ahead() sweeps our real footprint along the path,
        // so a robot parked at a home beside the road (0.25 m from its centre line on the
        // tables) leaves the road open while one touching the lane does not.
        planning::DynamicGridConfiguration d;
        d.own_radius = 0.0;
        d.safety_margin = config.neighbour_margin;
        d.stale_after = config.stale_after;
        d.max_speed = config.neighbour_max_speed;
        d.max_reach = config.neighbour_max_reach;
        return d;
      }()),
      lidar_(config.lidar),
      octomap_([&] {
        planning::OctoMapConfiguration o;
        o.resolution = config.grid_resolution;
        o.area = site_->site.bounds;
        o.projection_resolution = config.grid_resolution;  // must match the static grid's cells
        return o;
      }()),
      road_(config.route_graph ? *config.route_graph : site_->graph.graph),
      routes_(road_, grid_astar_),
      two_way_road_(site_->graph.graph),
      two_way_routes_(two_way_road_, grid_astar_) {
  reset_obstacles();
  sim_.warm_up(1.0, step_period());
  route_version_ = first_route_version(std::chrono::system_clock::now());
}

std::uint64_t first_route_version(std::chrono::system_clock::time_point now) {
  const auto unix_s = std::chrono::duration_cast<std::chrono::seconds>(now.time_since_epoch()).count();
  return static_cast<std::uint64_t>(std::max<std::int64_t>(0, unix_s - 1'700'000'000)) * 16;
}

std::uint64_t next_own_route_version(std::uint64_t current) {
  return (current + 2) & ~std::uint64_t{1};
}

void Forklift::reset_obstacles() {
  obstacles_.clear();
  for (const auto& o : site_->site.static_obstacles) {
    obstacles_[o.id] = o.enabled_at_start;
    static_grid_.set_obstacle_enabled(o.id, o.enabled_at_start);
  }
}

void Forklift::set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph) {
  site_ = std::move(site);
  config_.route_graph = std::move(route_graph);
  static_grid_ = make_static_grid(config_, *site_);
  reset_obstacles();
  // routes_ keeps a reference to road_: assigned in place, it plans on the new graph.
  road_ = planning::RoadPlanner(config_.route_graph ? *config_.route_graph : site_->graph.graph);
  two_way_road_ = planning::RoadPlanner(site_->graph.graph);
  grid_revision_ = std::numeric_limits<std::uint64_t>::max();  // hand the new grid to the planners
  seen_free_.clear();
  // The old map's route means nothing to the traffic manager of the new one.
  road_points_.clear();
  road_cum_.clear();
  pending_route_.reset();
  permit_ = {};
  executor_.replan();
}

bool Forklift::submit(const task::TaskOrder& order, std::string* why) {
  return executor_.submit(order, why);
}

bool Forklift::withdraw() {
  return executor_.cancel();
}

void Forklift::set_paused(bool paused) {
  if (paused) {
    executor_.pause();
  } else {
    executor_.resume();
  }
}

bool Forklift::set_obstacle(const std::string& id, bool enabled) {
  auto it = obstacles_.find(id);
  if (it == obstacles_.end() || it->second == enabled) return false;
  it->second = enabled;
  static_grid_.set_obstacle_enabled(id, enabled);
  const task::State s = executor_.state();
  executor_.replan();
  return s == task::State::kTrackPath || s == task::State::kGoHome || s == task::State::kWaiting;
}

void Forklift::set_standing_pallets(const std::map<int, Pose2>& standing) {
  std::vector<int> gone;
  for (const auto& p : pallets_.pallets()) {
    if (!p.carried && !standing.contains(p.id)) gone.push_back(p.id);
  }
  for (int id : gone) pallets_.remove(id);
  for (const auto& [id, pose] : standing) pallets_.place(id, pose);
}

void Forklift::set_neighbours(std::vector<Neighbour> neighbours) {
  neighbours_ = std::move(neighbours);
}

void Forklift::set_true_neighbours(std::vector<geometry::Polygon> footprints) {
  true_neighbours_ = std::move(footprints);
}

std::string Forklift::task_state() const {
  return task::to_string(executor_.state());
}

std::optional<std::string> Forklift::order_id() const {
  if (executor_.order()) return executor_.order()->order_id;
  return std::nullopt;
}

std::vector<geometry::Polygon> Forklift::uwb_blockers() const {
  std::vector<geometry::Polygon> out;
  for (const auto& o : site_->site.static_obstacles) {
    if (obstacles_.at(o.id)) out.push_back(o.polygon);
  }
  // A neighbour shadows an anchor only near the tag: the ray from an anchor at height z_a to the
  // tag at z_t rises above a robot of height h within (h - z_t) / (z_a - z_t) of the horizontal
  // distance. Anchors stand about 1 m high around the table, 2-4 m away, so only a robot within
  // a few centimetres to a dozen of our antenna blocks a range; treating its 2D outline as a wall
  // to every anchor would shadow most of the table.
  const Vec2 tag = sim_.estimate().position();
  // metres: (0.15 - 0.10) / (1.0 - 0.10) x 3 m, rounded up, on the table; it scales with the robot.
  const double reach = config_.uwb_shadow_reach;
  for (const auto& n : neighbours_) {
    const auto polygon = geometry::footprint_polygon(n.pose, n.footprint);
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec2& corner : polygon) nearest = std::min(nearest, geometry::distance(corner, tag));
    if (nearest <= reach || geometry::contains(polygon, tag)) out.push_back(polygon);
  }
  return out;
}

std::vector<std::size_t> Forklift::shadowed_anchors() const {
  std::vector<std::size_t> out;
  if (config_.anchor_shadow_margin < 0.0) return out;
  const auto& anchors = site_->site.uwb_anchors;
  const Vec2 tag = geometry::body_to_map(sim_.estimate(), config_.sim.uwb.antenna_offset);
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    const Vec2 anchor{anchors[i].x, anchors[i].y};
    for (const auto& o : site_->site.static_obstacles) {
      if (obstacles_.at(o.id) &&
          geometry::segment_polygon_distance(anchor, tag, o.polygon) <= config_.anchor_shadow_margin) {
        out.push_back(i);
        break;
      }
    }
  }
  // Three ranges fix a position; with fewer left, a biased fix still beats none for long.
  if (anchors.size() - out.size() < 3) out.clear();
  return out;
}

namespace {
/// The occupied cells of `layer` inside the footprint at `pose`, grown by `margin`, as indices
/// y * width + x in ascending order.
std::vector<int> footprint_cells(const planning::OccupancyGrid& layer, const Pose2& pose, const geometry::Footprint& fp,
                                 double margin) {
  std::vector<int> cells;
  const double hl = fp.length / 2.0 + margin;
  const double hw = fp.width / 2.0 + margin;
  const double reach = std::hypot(hl, hw);
  const double res = layer.resolution();
  const Vec2 o = layer.origin();
  const int x0 = static_cast<int>(std::floor((pose.x - reach - o.x) / res));
  const int x1 = static_cast<int>(std::floor((pose.x + reach - o.x) / res));
  const int y0 = static_cast<int>(std::floor((pose.y - reach - o.y) / res));
  const int y1 = static_cast<int>(std::floor((pose.y + reach - o.y) / res));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if (!layer.in_bounds(x, y) || !layer.occupied(x, y)) continue;
      const Vec2 b = geometry::map_to_body(pose, layer.cell_center(x, y));
      if (std::abs(b.x) <= hl && std::abs(b.y) <= hw) cells.push_back(y * layer.width() + x);
    }
  }
  return cells;
}

/// Whether the footprint at `pose` meets an occupied cell other than the `already_touched` ones
/// (sorted indices).
bool footprint_hits(const planning::OccupancyGrid& layer, const Pose2& pose, const geometry::Footprint& fp,
                    double margin, const std::vector<int>& already_touched) {
  for (int cell : footprint_cells(layer, pose, fp, margin)) {
    if (!std::binary_search(already_touched.begin(), already_touched.end(), cell)) return true;
  }
  return false;
}

/// Distance from `p` to the footprint standing at `pose`, 0 inside.
double footprint_distance(const Pose2& pose, const geometry::Footprint& fp, Vec2 p) {
  const Vec2 b = geometry::map_to_body(pose, p);
  return std::hypot(std::max(std::abs(b.x) - fp.length / 2.0, 0.0), std::max(std::abs(b.y) - fp.width / 2.0, 0.0));
}
}  // namespace

double Forklift::clearance_ahead() const {
  // How far the robot can move along its path before its footprint meets a cell of the dynamic
  // layer: the other robots from FleetView (grown by their speed x data age, or the stale rule)
  // and what the lidar sees [Forklift thesis, section 5.3]. The footprint itself is swept, not a point
  // against grown obstacles, because an obstacle beside the path meets the front corner first.
  const double kSample = config_.clearance_sample;
  const double kMargin = config_.clearance_margin;
  if (path_.size() < 2) return std::numeric_limits<double>::infinity();
  const auto& layer = dynamic_.dynamic_layer();
  if (layer.size() == 0) return std::numeric_limits<double>::infinity();
  // Where we are on the path: the projection onto the nearest segment.
  const Vec2 here = sim_.estimate().position();
  std::size_t segment = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path_.size(); ++i) {
    const double d = geometry::point_segment_distance(here, path_[i], path_[i + 1]);
    if (d < best) {
      best = d;
      segment = i;
    }
  }
  const Vec2 a = path_[segment];
  const Vec2 ab = path_[segment + 1] - a;
  const double len2 = geometry::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(geometry::dot(here - a, ab) / len2, 0.0, 1.0) : 0.0;
  Vec2 prev = a + t * ab;
  // Cells the footprint touches where it stands are no reason to stop: a robot that came to a
  // halt a little close to a parked body (grown by the margins) may drive on along a path that
  // leads away; deeper cells still stop it, and the safety stop refuses any move closer than
  // its gap.
  const std::vector<int> touched = footprint_cells(layer, sim_.estimate(), footprint(), kMargin);
  double travelled = 0.0;
  for (std::size_t i = segment + 1; i < path_.size() && travelled < config_.clearance_lookahead; ++i) {
    const Vec2 next = path_[i];
    const double len = geometry::distance(prev, next);
    if (len < 1e-9) continue;
    const double heading = std::atan2(next.y - prev.y, next.x - prev.x);
    for (double s = kSample; s <= len && travelled + s <= config_.clearance_lookahead; s += kSample) {
      const Vec2 p = prev + (s / len) * (next - prev);
      if (footprint_hits(layer, {p.x, p.y, heading}, footprint(), kMargin, touched)) {
        return std::max(0.0, travelled + s - kSample);
      }
    }
    travelled += len;
    prev = next;
  }
  return std::numeric_limits<double>::infinity();
}

void Forklift::step() {
  const double dt = step_period();
  const double t = sim_.time();

  if (t >= next_dynamic_update_) {
    next_dynamic_update_ = t + kDynamicUpdatePeriod;
    std::vector<planning::Neighbour> others;
    for (const auto& n : neighbours_) others.push_back({n.robot_id, n.pose, n.speed, n.age, n.footprint});
    // The lidar measures from where the robot really is; the robot files the scan under where it
    // believes it is, so localization error shows in its map as it would on real hardware.
    std::vector<geometry::Polygon> seen = true_neighbours_;
    for (const auto& o : site_->site.static_obstacles) {
      if (obstacles_.at(o.id)) seen.push_back(o.polygon);
    }
    planning::LidarScan scan = lidar_.scan(sim_.truth(), seen);
    scan.pose = sim_.estimate();
    near_returns_.clear();
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      const double r = scan.ranges[i];
      if (!(r < config_.safety_scan_range)) continue;
      const double a = scan.pose.yaw + scan.angle_min + static_cast<double>(i) * scan.angle_increment;
      near_returns_.push_back({scan.pose.x + r * std::cos(a), scan.pose.y + r * std::sin(a)});
    }
    octomap_.insert_scan(scan);
    dynamic_.update(static_grid_.permanent_grid(), others, &octomap_.sensed());
    // [Forklift thesis, Fig. 5.13]: a temporary obstacle goes once its area is seen free again.
    std::vector<std::string> cleared;
    for (const auto& [id, polygon] : static_grid_.temporaries()) {
      Vec2 centre{};
      bool free = true;
      for (const Vec2& corner : polygon) {
        free = free && !dynamic_.dynamic_layer().occupied_at(corner);
        centre = centre + (1.0 / static_cast<double>(polygon.size())) * corner;
      }
      free = free && !dynamic_.dynamic_layer().occupied_at(centre);
      seen_free_[id] = free ? seen_free_[id] + 1 : 0;
      if (seen_free_[id] >= kClearChecks) cleared.push_back(id);
    }
    for (const auto& id : cleared) {
      static_grid_.remove_temporary(id);
      seen_free_.erase(id);
      executor_.replan();
    }
  }

  // Another robot in the way: wait (WAITING, with the reason), and after a while plan around it
  // with a temporary obstacle [Forklift thesis, section 5.3]. Under traffic control the robot also
  // stops at the end of its grant; the neighbour check stays underneath as the safety layer.
  const double clearance = clearance_ahead();
  const double room = traffic_room();
  const bool driving = executor_.state() == task::State::kTrackPath || executor_.state() == task::State::kGoHome ||
                       (executor_.state() == task::State::kWaiting && (blocked_by_neighbour_ || held_by_traffic_));
  const bool blocked = driving && clearance <= config_.stop_distance;
  const bool held = driving && room <= 0.0;
  if (blocked != blocked_by_neighbour_ || held != held_by_traffic_) {
    const bool was_stopped = blocked_by_neighbour_ || held_by_traffic_;
    if (blocked != blocked_by_neighbour_) blocked_since_ = blocked ? t : -1.0;
    blocked_by_neighbour_ = blocked;
    held_by_traffic_ = held;
    if (was_stopped != (blocked || held)) executor_.set_blocked(blocked || held);
  }
  // Counted from the first hold on this siding, not reset when a hold flickers at its end.
  if (in_siding_ && held && siding_held_since_ < 0.0) siding_held_since_ = t;
  if (in_siding_ && siding_held_since_ >= 0.0 && t - siding_held_since_ > config_.siding_timeout && !pending_route_) {
    // Nobody called it back (a manager restarted meanwhile has no record of the siding): plan
    // the way on from here, as a route of its own the manager then grants.
    in_siding_ = false;
    executor_.replan();
  }
  if (blocked) {
    // Name the nearest robot: what an operator needs to see why this one waits.
    const Pose2 here = sim_.estimate();
    std::string nearest = "another robot";
    double nearest_gap = std::numeric_limits<double>::infinity();
    for (const auto& n : neighbours_) {
      const double gap = geometry::convex_polygons_distance(geometry::footprint_polygon(here, footprint()),
                                                            geometry::footprint_polygon(n.pose, n.footprint));
      if (gap < nearest_gap) {
        nearest_gap = gap;
        nearest = n.robot_id;
      }
    }
    const bool robot_ahead = std::isfinite(nearest_gap) && nearest_gap < 0.5;
    detail_ = robot_ahead ? "robot " + nearest + " ahead" : "an obstacle ahead";
    note_safety_stop(t, robot_ahead ? nearest : std::string{});
  } else if (held) {
    detail_ = permit_.blocked_by.empty() ? "waiting for a traffic grant" : "waiting for traffic: road held by " + [&] {
      std::string ids;
      for (const auto& id : permit_.blocked_by) ids += (ids.empty() ? "" : ", ") + id;
      return ids;
    }();
  } else if (driving && (detail_.ends_with(" ahead") || detail_.starts_with("waiting for"))) {
    detail_.clear();
  }
  // Under traffic control the manager routes around robots (re-routes, sidings) on the one-way
  // graph; a temporary obstacle there could cut the only way in a corridor's direction.
  if (blocked && !config_.traffic && t - blocked_since_ > kDetourAfter) {
    const Pose2 here = sim_.estimate();
    const double size = config_.temporary_size;
    const Vec2 ahead{here.x + (clearance + size / 2) * std::cos(here.yaw),
                     here.y + (clearance + size / 2) * std::sin(here.yaw)};
    static_grid_.add_temporary("tmp-" + std::to_string(next_temporary_++), box_around(ahead, size));
    blocked_since_ = t;
    blocked_by_neighbour_ = false;
    if (!held_by_traffic_) executor_.set_blocked(false);
    executor_.replan();
    detail_ = "planning around a robot in the way";
  }

  std::vector<perception::MarkerDetection> detections;
  if (camera_.frame_due(t)) detections = camera_.capture(t, sim_.truth(), pallets_.markers());
  // The end of the grant acts like an obstacle stop_distance beyond it: the follower slows
  // towards it and the robot is held as it gets there.
  const task::TaskOutput out =
      executor_.step({t, sim_.estimate(), detections, std::min(clearance, room + config_.stop_distance)});

  const perception::ForkEvent fork = pallets_.update(0, sim_.truth(), out.fork_up);
  switch (fork.kind) {
    case perception::ForkEvent::Kind::kLifted:
      carried_pallet_ = fork.pallet_id;
      events_.push_back({ForkliftEvent::Kind::kLifted, order_id().value_or(""), "", fork.pallet_id, {}});
      break;
    case perception::ForkEvent::Kind::kPutDown:
      last_put_down_ = std::pair{fork.pallet_id, pallets_.find(fork.pallet_id)->pose};
      carried_pallet_ = -1;
      break;
    case perception::ForkEvent::Kind::kLiftMissed:
    case perception::ForkEvent::Kind::kNone:
      break;
  }

  command_ = safe(out.twist);
  const auto blockers = uwb_blockers();
  sim_.step(command_, dt, blockers, shadowed_anchors());
  answer_plan_requests();
  collect_reports();
}

control::BodyTwist Forklift::safe(const control::BodyTwist& cmd) const {
  // The last line of defence under traffic and local planning, in every state and every
  // manoeuvre (backing out of a drop too): a command that would bring this footprint within
  // `safety_gap` of another robot within the horizon, and closer than it is now, becomes a stop.
  // Moving apart stays allowed, so two robots that met can always separate.
  if (cmd == control::BodyTwist{} || !moves_too_close(cmd)) return cmd;
  // Refused close beside a body (a turn on the spot would swing a corner into it): the mecanum
  // base steps straight away from the nearest lidar return, slowly, when that step is safe, so
  // the robot makes room for the turn instead of standing there for good.
  const double kEscapeWithin = config_.escape_within;  // metres: only this close to a body
  const double kEscapeSpeed = config_.escape_speed;    // m/s
  const Pose2 now = sim_.estimate();
  const Vec2* nearest = nullptr;
  double nearest_gap = kEscapeWithin;
  for (const Vec2& p : near_returns_) {
    const double gap = footprint_distance(now, footprint(), p);
    if (gap < nearest_gap) {
      nearest_gap = gap;
      nearest = &p;
    }
  }
  if (nearest == nullptr) return {};
  const Vec2 away = geometry::map_to_body(now, *nearest);
  const double norm = std::hypot(away.x, away.y);
  if (norm < 1e-6) return {};
  const control::BodyTwist escape{-kEscapeSpeed * away.x / norm, -kEscapeSpeed * away.y / norm, 0.0};
  return moves_too_close(escape) ? control::BodyTwist{} : escape;
}

bool Forklift::moves_too_close(const control::BodyTwist& cmd) const {
  // The footprint is swept over the horizon (passing a corner, the closest approach lies inside
  // it) and checked against two views of the others: the poses they publish (grown by what they
  // may have moved since), and the lidar's own returns, which a bias of this robot's estimate
  // does not move.
  constexpr double kHorizon = 0.4;  // sim seconds of the current command looked ahead
  constexpr int kSweepSteps = 4;
  if (neighbours_.empty() && near_returns_.empty()) return false;
  const Pose2 now = sim_.estimate();
  std::array<Pose2, kSweepSteps> ahead;
  std::array<geometry::Polygon, kSweepSteps> mine_ahead;
  for (int k = 0; k < kSweepSteps; ++k) {
    ahead[k] = control::integrate_twist(now, cmd, kHorizon * (k + 1) / kSweepSteps);
    mine_ahead[k] = geometry::footprint_polygon(ahead[k], footprint());
  }
  const auto mine_now = geometry::footprint_polygon(now, footprint());
  for (const auto& n : neighbours_) {
    const double moved = n.age > config_.stale_after ? config_.neighbour_max_speed * n.age : n.speed * n.age;
    const auto theirs = geometry::footprint_polygon(n.pose, n.footprint, std::min(moved, 1.0));
    const double gap_now = geometry::convex_polygons_distance(mine_now, theirs);
    for (const auto& mine : mine_ahead) {
      const double gap = geometry::convex_polygons_distance(mine, theirs);
      if (gap < config_.safety_gap && gap < gap_now) return true;
    }
  }
  for (const Vec2& p : near_returns_) {
    const double gap_now = footprint_distance(now, footprint(), p);
    for (const Pose2& pose : ahead) {
      const double gap = footprint_distance(pose, footprint(), p);
      if (gap < config_.safety_gap && gap < gap_now) return true;
    }
  }
  return false;
}

void Forklift::answer_plan_requests() {
  const auto request = executor_.take_plan_request();
  if (!request) return;
  if (static_grid_.revision() != grid_revision_) {
    // Planners cache on the grid: hand them the new one only when an obstacle changed.
    auto grid = std::make_shared<const planning::OccupancyGrid>(static_grid_.grid());
    road_.set_obstacles(*grid);
    if (config_.route_graph) two_way_road_.set_obstacles(*grid);
    grid_astar_.set_grid(grid);
    grid_revision_ = static_grid_.revision();
  }
  if (pending_route_) {
    // The traffic manager re-routed this robot (a way round, a siding, or back from one).
    const TrafficPermit permit = std::move(*pending_route_);
    pending_route_.reset();
    adopt_traffic_route(permit);
    executor_.path_received(request->id, planning::poses_along(path_));
    return;
  }
  planning::Route route = routes_.plan(sim_.estimate(), request->goal);
  if (config_.route_graph && route.status != planning::PlanStatus::kFound) {
    planning::Route both_ways = two_way_routes_.plan(sim_.estimate(), request->goal);
    if (both_ways.status == planning::PlanStatus::kFound) route = std::move(both_ways);
  }
  if (route.status == planning::PlanStatus::kFound && route.points.size() >= 2) {
    adopt_path(route);
    executor_.path_received(request->id, planning::poses_along(route.points));
  } else {
    // Blocked by a static obstacle [Forklift thesis, Fig. 5.11] or no way at all: wait and ask again.
    path_.clear();
    detail_ = route.status == planning::PlanStatus::kBlockedPartial ? "route blocked by an obstacle" : "no route";
    executor_.plan_failed(request->id);
  }
}

void Forklift::collect_reports() {
  for (const task::Transition& tr : executor_.take_transitions()) {
    if (tr.to != tr.from) {
      events_.push_back({ForkliftEvent::Kind::kState, order_id().value_or(""), task::to_string(tr.to), -1, {}});
      if (tr.to != task::State::kWaiting && !blocked_by_neighbour_) detail_.clear();
    }
    if (tr.to_phase != tr.from_phase && tr.to_phase != orders::OrderPhase::kNone) {
      events_.push_back(
          {ForkliftEvent::Kind::kPhase, order_id().value_or(""), std::string(orders::to_string(tr.to_phase)), -1, {}});
    }
  }
  for (const task::TaskReport& r : executor_.take_reports()) {
    using K = task::TaskReport::Kind;
    switch (r.kind) {
      case K::kDropped: {
        ForkliftEvent e{ForkliftEvent::Kind::kDone, r.order_id, r.area_id, -1, {}};
        if (last_put_down_) {
          e.pallet_id = last_put_down_->first;
          e.pallet_pose = last_put_down_->second;
          last_put_down_.reset();
        }
        events_.push_back(e);
        break;
      }
      case K::kAreaEmpty: {
        std::string text = "loading area " + r.area_id + " is empty";
        if (!r.detail.empty()) text += " (" + r.detail + ")";
        events_.push_back({ForkliftEvent::Kind::kAreaEmpty, r.order_id, text, -1, {}});
        break;
      }
      case K::kFailed:
        events_.push_back({ForkliftEvent::Kind::kFailed, r.order_id, r.detail, -1, {}});
        break;
      case K::kHomeReached:
      case K::kArrived:
        path_.clear();
        path_cum_.clear();
        road_points_.clear();  // parked beside the road: it holds no road any more
        road_cum_.clear();
        if (r.kind == K::kArrived) {
          events_.push_back({ForkliftEvent::Kind::kDone, r.order_id, r.area_id, -1, {}});
        } else {
          events_.push_back({ForkliftEvent::Kind::kHome, "", "", -1, {}});
        }
        break;
      case K::kAccepted:
      case K::kPicked:
      case K::kCancelled:
        break;
    }
  }
}

namespace {
std::vector<double> cumulative_lengths(const std::vector<Vec2>& points) {
  std::vector<double> cum(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) cum[i] = cum[i - 1] + geometry::distance(points[i - 1], points[i]);
  return cum;
}
}  // namespace

void Forklift::adopt_path(const planning::Route& route) {
  path_ = route.points;
  path_cum_ = cumulative_lengths(path_);
  path_s_ = 0.0;
  in_siding_ = false;
  siding_held_since_ = -1.0;
  safety_stop_ = {};  // a stop is reported for the route it happened on, after lasting on it
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
  route_version_ = next_own_route_version(route_version_);
}

void Forklift::adopt_traffic_route(const TrafficPermit& permit) {
  const auto& graph = site_->graph.graph;
  // Compared with the own plan's last point, not the route being driven: coming back from a
  // siding, that route is the siding's, and the robot still has to leave the road at the goal.
  const bool to_goal = !permit.siding && goal_point_ >= 0 && permit.route.back() == goal_point_;
  std::vector<Vec2> road;
  for (int id : permit.route)
    road.push_back({graph.points[static_cast<std::size_t>(id)].x, graph.points[static_cast<std::size_t>(id)].y});
  const Vec2 here = sim_.estimate().position();
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
  path_s_ = 0.0;
  road_points_ = permit.route;
  route_version_ = permit.version;
  in_siding_ = permit.siding;
  siding_held_since_ = -1.0;
  safety_stop_ = {};
  detail_ = permit.siding ? "yielding on a siding" : "re-routed by traffic";
}

double Forklift::path_position() const {
  // The projection onto the path near where the robot was last found: a path may pass close to
  // itself, and progress must not jump.
  if (path_.size() < 2) return 0.0;
  const Vec2 here = sim_.estimate().position();
  double best_d = std::numeric_limits<double>::infinity();
  double best_s = path_s_;
  for (std::size_t i = 0; i + 1 < path_.size(); ++i) {
    if (path_cum_[i + 1] < path_s_ - 0.05) continue;
    if (path_cum_[i] > path_s_ + 0.30) break;
    const Vec2 a = path_[i];
    const Vec2 ab = path_[i + 1] - a;
    const double len2 = geometry::dot(ab, ab);
    const double u = len2 > 0.0 ? std::clamp(geometry::dot(here - a, ab) / len2, 0.0, 1.0) : 0.0;
    const double d = geometry::distance(here, a + u * ab);
    if (d < best_d) {
      best_d = d;
      best_s = path_cum_[i] + u * std::sqrt(len2);
    }
  }
  return best_s;
}

double Forklift::traffic_room() {
  if (!config_.traffic || road_points_.empty() || path_.size() < 2) return std::numeric_limits<double>::infinity();
  path_s_ = path_position();
  if (permit_.version != route_version_ || permit_.granted_index < 0) {
    // No grant for this route yet: stand still, not even turning on the spot; beside a lane a
    // turn sweeps the footprint into it. The manager admits the robot once its entry is free.
    return -path_s_ - 1e-9;
  }
  const bool whole_route = permit_.granted_index + 1 >= static_cast<int>(road_points_.size());
  if (whole_route && !in_siding_) return std::numeric_limits<double>::infinity();
  double allowed = road_start_ + permit_.granted_distance;
  // On a siding, stop just short of its end: the follower would take the end for the goal.
  if (in_siding_) allowed = std::min(allowed, road_start_ + road_cum_.back() - config_.siding_end_margin);
  return allowed - path_s_;
}

void Forklift::set_traffic_grant(const TrafficPermit& permit) {
  if (!config_.traffic) return;
  if (!permit.route.empty() && permit.version > route_version_ && !pending_route_) {
    pending_route_ = permit;
    executor_.replan();
  }
  if (!pending_route_) permit_ = permit;
}

bool Forklift::SafetyStop::current(double t, Vec2 here, double moved) const {
  return !robot_id.empty() && t - last_seen <= kStopGap && geometry::distance(here, where) <= moved;
}

void Forklift::note_safety_stop(double t, const std::string& nearest) {
  if (nearest.empty()) return;
  const Vec2 here = sim_.estimate().position();
  if (nearest != safety_stop_.robot_id || !safety_stop_.current(t, here, config_.stop_moved))
    safety_stop_ = {nearest, t, here, t};
  safety_stop_.last_seen = t;
}

TrafficRoute Forklift::traffic_route() const {
  TrafficRoute r;
  r.version = route_version_;
  r.points = road_points_;
  if (!road_points_.empty()) r.progress = std::clamp(path_s_ - road_start_, 0.0, road_cum_.back());
  const double t = sim_.time();
  if (!road_points_.empty() && safety_stop_.current(t, sim_.estimate().position(), config_.stop_moved) &&
      t - safety_stop_.since >= kReportStopAfter) {
    r.stopped_for.push_back(safety_stop_.robot_id);
  }
  return r;
}

std::vector<ForkliftEvent> Forklift::take_events() {
  std::vector<ForkliftEvent> out;
  out.swap(events_);
  return out;
}

}  // namespace fleet::robot
