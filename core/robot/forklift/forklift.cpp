#include "robot/forklift/forklift.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fleet::robot {

using geometry::Pose2;
using geometry::Vec2;

namespace {

constexpr double kDynamicUpdatePeriod = 0.1;  // sim seconds between dynamic-grid rebuilds (10 Hz)
constexpr double kDetourAfter = 3.0;          // sim seconds blocked before a temporary obstacle goes in
constexpr int kClearChecks = 3;               // dynamic updates a temporary must be seen free
NavigationParams navigation_params(const ForkliftConfig& c) {
  return {
      .grid_resolution = c.grid_resolution,
      .route_graph = c.route_graph,
      .both_ways_when_closed = true,
      .routes = {},
      .lidar = c.lidar,
      .follower = {.traffic = c.traffic, .siding_timeout = c.siding_timeout, .siding_end_margin = c.siding_end_margin},
      .safety = {.safety_gap = c.safety_gap,
                 .stale_after = c.stale_after,
                 .neighbour_max_speed = c.neighbour_max_speed,
                 .scan_range = c.safety_scan_range,
                 .escape_within = c.escape_within,
                 .escape_speed = c.escape_speed,
                 .stop_moved = c.stop_moved}};
}

geometry::Polygon box_around(Vec2 c, double side) {
  const double h = side / 2.0;
  return {{c.x - h, c.y - h}, {c.x + h, c.y - h}, {c.x + h, c.y + h}, {c.x - h, c.y + h}};
}

}  // namespace

Forklift::Forklift(const ForkliftConfig& config, std::shared_ptr<const map::SiteMap> site, const Pose2& home,
                   std::uint64_t seed, std::uint64_t stream, std::unique_ptr<ItemHandler> items)
    : config_(config),
      nav_(navigation_params(config), std::move(site), config.sim.forklift.footprint),
      sim_(config.sim, nav_.site().site, home, seed, stream),
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
        d.reported_tolerance = config.reported_tolerance;
        return d;
      }()),
      octomap_([&] {
        planning::OctoMapConfiguration o;
        o.resolution = config.grid_resolution;
        o.area = nav_.site().site.bounds;
        o.projection_resolution = config.grid_resolution;  // must match the static grid's cells
        return o;
      }()),
      items_(std::move(items)) {
  // At start, like the planners' tables (Navigation): the lidar map, every leaf of the site from the
  // start (the ground free until seen otherwise), not one more for each stretch of floor the robot
  // first sees.
  octomap_.assume_free();
  sim_.warm_up(1.0, step_period());
}

void Forklift::set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph) {
  nav_.set_site(std::move(site), std::move(route_graph));
  seen_free_.clear();
  executor_.replan();
}

std::string Forklift::refusal(orders::OrderKind kind) const {
  if (kind == orders::OrderKind::kPick && !items_) return "a " + config_.type_name + " performs no pickItem";
  if (kind == orders::OrderKind::kTransport && !config_.forks) return "a " + config_.type_name + " has no forks";
  return "";
}

bool Forklift::submit(const task::TaskOrder& order, std::string* why) {
  if (std::string no = refusal(order.kind); !no.empty()) {
    if (why) *why = std::move(no);
    return false;
  }
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
  if (!nav_.set_obstacle(id, enabled)) return false;
  const task::State s = executor_.state();
  executor_.replan();
  return s == task::State::kTrackPath || s == task::State::kGoHome || s == task::State::kWaiting;
}

void Forklift::set_standing_loads(const std::map<int, Pose2>& standing) {
  std::vector<int> gone;
  for (const auto& p : pallets_.pallets()) {
    if (!p.carried && !standing.contains(p.id)) gone.push_back(p.id);
  }
  for (int id : gone) pallets_.remove(id);
  for (const auto& [id, pose] : standing) pallets_.place(id, pose);
}

RobotStatus Forklift::status() const {
  const ItemHandler::LoaderProgress loading = items_ ? items_->loader_progress() : ItemHandler::LoaderProgress{};
  return {.time = time(),
          .truth = sim_.truth(),
          .estimate = sim_.estimate(),
          .covariance = sim_.covariance(),
          .localization_score = sim_.localization_score(),
          .command = command_,
          .task_state = task::to_string(executor_.state()),
          .detail = reports_.detail(),
          .order_id = order_id(),
          .carried_load = carried_pallet_,
          .footprint = footprint(),
          .held_by_traffic = held_by_traffic_,
          .walk_stop = loading.walk_stop,
          .boxes_loaded = loading.boxes_loaded};
}

std::optional<std::string> Forklift::order_id() const {
  if (executor_.order()) return executor_.order()->order_id;
  return std::nullopt;
}

namespace {
/// Calls `visit(index)` for each occupied cell of `layer` inside the footprint at `pose`, grown by
/// `margin`, index y * width + x in ascending order, until it returns true; true when one did.
template <typename Visit>
bool visit_footprint_cells(const planning::OccupancyGrid& layer, const Pose2& pose, const geometry::Footprint& fp,
                           double margin, Visit visit) {
  const double hl = fp.length / 2.0 + margin;
  const double hw = fp.width / 2.0 + margin;
  const double reach = std::hypot(hl, hw);
  const double res = layer.resolution();
  const Vec2 o = layer.origin();
  const int x0 = std::max(0, static_cast<int>(std::floor((pose.x - reach - o.x) / res)));
  const int x1 = std::min(layer.width() - 1, static_cast<int>(std::floor((pose.x + reach - o.x) / res)));
  const int y0 = std::max(0, static_cast<int>(std::floor((pose.y - reach - o.y) / res)));
  const int y1 = std::min(layer.height() - 1, static_cast<int>(std::floor((pose.y + reach - o.y) / res)));
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if (!layer.occupied(x, y)) continue;
      const Vec2 b = geometry::map_to_body(pose, layer.cell_center(x, y));
      if (std::abs(b.x) <= hl && std::abs(b.y) <= hw && visit(y * layer.width() + x)) return true;
    }
  }
  return false;
}

/// The occupied cells of `layer` inside the footprint at `pose`, grown by `margin`, as indices
/// y * width + x in ascending order.
std::vector<int> footprint_cells(const planning::OccupancyGrid& layer, const Pose2& pose, const geometry::Footprint& fp,
                                 double margin) {
  std::vector<int> cells;
  visit_footprint_cells(layer, pose, fp, margin, [&](int cell) {
    cells.push_back(cell);
    return false;
  });
  return cells;
}

/// Whether the footprint at `pose` meets an occupied cell other than the `already_touched` ones
/// (sorted indices).
bool footprint_hits(const planning::OccupancyGrid& layer, const Pose2& pose, const geometry::Footprint& fp,
                    double margin, const std::vector<int>& already_touched) {
  return visit_footprint_cells(layer, pose, fp, margin, [&](int cell) {
    return !std::binary_search(already_touched.begin(), already_touched.end(), cell);
  });
}

/// A path walked by arc length: the point `s` metres along it, clamped to its ends.
class PathLine {
 public:
  explicit PathLine(std::vector<Vec2> points) : points_(std::move(points)) {
    cumulative_.push_back(0.0);
    for (std::size_t i = 1; i < points_.size(); ++i) {
      cumulative_.push_back(cumulative_.back() + geometry::distance(points_[i - 1], points_[i]));
    }
  }
  double length() const { return cumulative_.back(); }
  Vec2 point_at(double s) const {
    if (s <= 0.0) return points_.front();
    for (std::size_t i = 1; i < points_.size(); ++i) {
      if (s <= cumulative_[i]) {
        const double len = cumulative_[i] - cumulative_[i - 1];
        return len > 1e-12 ? points_[i - 1] + ((s - cumulative_[i - 1]) / len) * (points_[i] - points_[i - 1])
                           : points_[i];
      }
    }
    return points_.back();
  }

 private:
  std::vector<Vec2> points_;
  std::vector<double> cumulative_;
};

}  // namespace

double Forklift::clearance_ahead(geometry::Pose2& blocked_at) const {
  // How far the robot can move along its path before its footprint meets a cell of the dynamic
  // layer: the other robots from FleetView (grown by their speed x data age, or the stale rule)
  // and what the lidar sees [Forklift thesis, section 5.3]. The footprint itself is swept, not a point
  // against grown obstacles, because an obstacle beside the path meets the front corner first.
  const double kSample = config_.clearance_sample;        // metres between swept poses
  const double kMargin = config_.clearance_margin;        // metres around our footprint
  const double kLookahead = config_.clearance_lookahead;  // metres of path checked [Forklift thesis, section 5.3]
  const std::vector<Vec2>& path = nav_.follower().path();
  if (path.size() < 2) return std::numeric_limits<double>::infinity();
  const auto& layer = dynamic_.dynamic_layer();
  if (layer.size() == 0) return std::numeric_limits<double>::infinity();
  // Where we are on the path: the projection onto the nearest segment.
  const Vec2 here = sim_.estimate().position();
  std::size_t segment = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double d = geometry::point_segment_distance(here, path[i], path[i + 1]);
    if (d < best) {
      best = d;
      segment = i;
    }
  }
  // Backing up and coming back, the path covers the same ground twice: the leg it is on decides.
  if (const auto on_leg = nav_.follower().segment_on_leg()) segment = *on_leg;
  const Vec2 a = path[segment];
  const Vec2 ab = path[segment + 1] - a;
  const double len2 = geometry::dot(ab, ab);
  const double t = len2 > 0.0 ? std::clamp(geometry::dot(here - a, ab) / len2, 0.0, 1.0) : 0.0;
  Vec2 prev = a + t * ab;
  // Cells the footprint touches where it stands are no reason to stop: a robot that came to a
  // halt a little close to a parked body (grown by the margins) may drive on along a path that
  // leads away; deeper cells still stop it, and the safety stop refuses any move closer than
  // its gap.
  const std::vector<int> touched = footprint_cells(layer, sim_.estimate(), footprint(), kMargin);
  // The body is swept turned along each segment, except on the join: the short first leg from
  // where the robot stood when it planned to its route's first point. The follower does not turn
  // along that leg but steers for the point one lookahead further on [Forklift thesis, eq. 6.3],
  // and so is the body swept there. Turned along a 0.25 m diagonal, a forklift leaving its
  // parking stall swung its corner into the one parked in the next stall.
  const double steer = config_.task.follower.lookahead;
  const bool on_join = segment == 0 && geometry::distance(path[0], path[1]) < steer;
  std::optional<PathLine> line;
  if (on_join) line.emplace(std::vector<Vec2>(path.begin(), path.end()));
  double travelled = 0.0;
  for (std::size_t i = segment + 1; i < path.size() && travelled < kLookahead; ++i) {
    const Vec2 next = path[i];
    const double len = geometry::distance(prev, next);
    if (len < 1e-9) continue;
    const double along = i == 1 ? geometry::distance(path[0], prev) : 0.0;
    for (double s = kSample; s <= len && travelled + s <= kLookahead; s += kSample) {
      const Vec2 p = prev + (s / len) * (next - prev);
      Vec2 towards = next;
      if (on_join && i == 1) towards = line->point_at(along + s + steer);
      const double heading = std::atan2(towards.y - p.y, towards.x - p.x);
      if (footprint_hits(layer, {p.x, p.y, heading}, footprint(), kMargin, touched)) {
        blocked_at = {p.x, p.y, heading};
        return std::max(0.0, travelled + s - kSample);
      }
    }
    travelled += len;
    prev = next;
  }
  return std::numeric_limits<double>::infinity();
}

void Forklift::update_surroundings() {
  std::vector<planning::Neighbour> others;
  for (const auto& n : nav_.neighbours()) others.push_back({n.robot_id, n.pose, n.speed, n.age, n.footprint});
  // The lidar measures from where the robot really is; the robot files the scan under where it
  // believes it is, so localization error shows in its map as it would on real hardware.
  const planning::LidarScan scan = nav_.scan(sim_.truth(), sim_.estimate());
  nav_.safety().take_scan(scan);
  octomap_.insert_scan(scan);
  dynamic_.update(nav_.static_grid().permanent_grid(), others, &octomap_.sensed());
  // [Forklift thesis, Fig. 5.13]: a temporary obstacle goes once its area is seen free again.
  std::vector<std::string> cleared;
  for (const auto& [id, polygon] : nav_.static_grid().temporaries()) {
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
    nav_.static_grid().remove_temporary(id);
    seen_free_.erase(id);
    executor_.replan();
  }
}

double Forklift::follow_traffic(double t, double clearance, const geometry::Pose2& blocked_at) {
  // Another robot in the way: wait (WAITING, with the reason), and after a while plan around it
  // with a temporary obstacle [Forklift thesis, section 5.3]. Under traffic control the robot also
  // stops at the end of its grant; the neighbour check stays underneath as the safety layer.
  const control::PathFollower& controller = executor_.follower();
  const double room = nav_.follower().room(
      sim_.estimate().position(), TrafficFollower::ControllerLeg{controller.length(), controller.leg_start_s()});
  const bool driving = executor_.state() == task::State::kTrackPath || executor_.state() == task::State::kGoHome ||
                       (executor_.state() == task::State::kWaiting && (blocked_by_neighbour_ || held_by_traffic_));
  const bool blocked = driving && clearance <= stop_distance();
  const bool held = driving && room <= 0.0;
  if (blocked != blocked_by_neighbour_ || held != held_by_traffic_) {
    const bool was_stopped = blocked_by_neighbour_ || held_by_traffic_;
    if (blocked != blocked_by_neighbour_) blocked_since_ = blocked ? t : -1.0;
    blocked_by_neighbour_ = blocked;
    held_by_traffic_ = held;
    if (was_stopped != (blocked || held)) executor_.set_blocked(blocked || held);
  }
  if (nav_.follower().siding_timed_out(t, held)) executor_.replan();
  if (blocked) {
    const Pose2 here = sim_.estimate();
    // The robot whose cells stopped it, nearest the swept pose that met them: they are grown by
    // its speed and data age (a standing one that reports seldom is grown most), so its body may
    // be a metre off that pose. Measured from where this robot stands instead, a large vehicle
    // that stops its stopping distance short of the cells is further than that from their robot.
    const std::string ahead = nav_.safety().robot_within(blocked_at, nav_.neighbours(), 1.0);
    reports_.stopped_ahead(ahead);
    nav_.safety().note(t, here.position(), ahead);
  } else if (held) {
    reports_.held_by_traffic(nav_.follower().blocked_by());
  } else if (driving) {
    reports_.driving_on();
  }
  // Under traffic control the manager routes around robots (re-routes, sidings) on the one-way
  // graph; a temporary obstacle there could cut the only way in a corridor's direction.
  if (blocked && !config_.traffic && t - blocked_since_ > kDetourAfter) {
    const Pose2 here = sim_.estimate();
    const double size = config_.temporary_size;
    const Vec2 ahead{here.x + (clearance + size / 2) * std::cos(here.yaw),
                     here.y + (clearance + size / 2) * std::sin(here.yaw)};
    nav_.static_grid().add_temporary("tmp-" + std::to_string(next_temporary_++), box_around(ahead, size));
    blocked_since_ = t;
    blocked_by_neighbour_ = false;
    if (!held_by_traffic_) executor_.set_blocked(false);
    executor_.replan();
    reports_.set_detail("planning around a robot in the way");
  }
  return room;
}

void Forklift::step() {
  const double dt = step_period();
  const double t = sim_.time();
  if (t >= next_dynamic_update_) {
    next_dynamic_update_ = t + kDynamicUpdatePeriod;
    update_surroundings();
  }
  Pose2 blocked_at = sim_.estimate();
  const double clearance = clearance_ahead(blocked_at);
  const double room = follow_traffic(t, clearance, blocked_at);

  std::vector<perception::MarkerDetection> detections;
  if (camera_.frame_due(t)) detections = camera_.capture(t, sim_.truth(), pallets_.markers());
  // The end of the grant acts like an obstacle stop_distance beyond it: the follower slows
  // towards it, is held as it gets there, and steers as if the path ran straight on past it.
  const task::TaskOutput out = executor_.step(
      {t, sim_.estimate(), detections,
       std::min(clearance + config_.stop_distance - stop_distance(), room + config_.stop_distance), room});

  const perception::ForkEvent fork = pallets_.update(0, sim_.truth(), out.fork_up);
  switch (fork.kind) {
    case perception::ForkEvent::Kind::kLifted:
      carried_pallet_ = fork.pallet_id;
      reports_.add({RobotEvent::Kind::kLifted, order_id().value_or(""), "", fork.pallet_id, {}});
      break;
    case perception::ForkEvent::Kind::kPutDown:
      last_put_down_ = std::pair{fork.pallet_id, pallets_.find(fork.pallet_id)->pose};
      carried_pallet_ = -1;
      break;
    case perception::ForkEvent::Kind::kLiftMissed:
    case perception::ForkEvent::Kind::kNone:
      break;
  }

  if (items_) items_->step(t, executor_, nav_.site().site, reports_);
  command_ = nav_.safety().safe(out.twist, sim_.estimate(), nav_.neighbours());
  const auto blockers = uwb_blockers();
  sim_.step(command_, dt, blockers, shadowed_anchors());
  answer_plan_requests();
  collect_reports();
}

void Forklift::answer_plan_requests() {
  const auto request = executor_.take_plan_request();
  if (!request) return;
  if (auto permit = nav_.follower().take_route()) {
    // The traffic manager re-routed this robot (a way round, a siding, or back from one).
    nav_.follower().adopt_route(*permit, nav_.site().graph.graph, sim_.estimate().position());
    arrival_area_ = arrival_sweep(place_of(request->purpose));
    if (!config_.stop_outlasts_reroute) nav_.safety().clear();
    reports_.set_detail(permit->siding ? "yielding on a siding" : "re-routed by traffic");
    executor_.path_received(request->id, planning::poses_along(nav_.follower().path()));
    return;
  }
  planning::Route route = nav_.plan(sim_.estimate(), request->goal);
  if (route.status == planning::PlanStatus::kFound && route.points.size() >= 2) {
    nav_.follower().adopt_plan(route);
    arrival_area_ = arrival_sweep(place_of(request->purpose));
    nav_.safety().clear();
    executor_.path_received(request->id, planning::poses_along(route.points));
  } else {
    // Blocked by a static obstacle [Forklift thesis, Fig. 5.11] or no way at all: wait and ask again.
    nav_.follower().drop_path();
    reports_.set_detail(route.status == planning::PlanStatus::kBlockedPartial ? "route blocked by an obstacle"
                                                                              : "no route");
    executor_.plan_failed(request->id);
  }
}

void Forklift::collect_reports() {
  for (const task::Transition& tr : executor_.take_transitions()) {
    if (tr.to != tr.from) {
      reports_.state_changed(order_id().value_or(""), task::to_string(tr.to),
                             tr.to == task::State::kWaiting || blocked_by_neighbour_);
    }
    if (tr.to_phase != tr.from_phase) reports_.phase_changed(order_id().value_or(""), tr.to_phase);
  }
  if (executor_.waits_for_release() && executor_.state() == task::State::kWaiting) {
    reports_.set_detail(model::kDetailWaitsForTransporter);
  }
  for (const task::TaskReport& r : executor_.take_reports()) {
    using K = task::TaskReport::Kind;
    switch (r.kind) {
      case K::kDropped: {
        RobotEvent e{RobotEvent::Kind::kDone, r.order_id, r.area_id, -1, {}};
        if (last_put_down_) {
          e.load_id = last_put_down_->first;
          e.load_pose = last_put_down_->second;
          last_put_down_.reset();
        }
        reports_.add(e);
        break;
      }
      case K::kAreaEmpty: {
        std::string text = "loading area " + r.area_id + " is empty";
        if (!r.detail.empty()) text += " (" + r.detail + ")";
        reports_.add({RobotEvent::Kind::kAreaEmpty, r.order_id, text, -1, {}});
        break;
      }
      case K::kFailed:
        reports_.add({RobotEvent::Kind::kFailed, r.order_id, r.detail, -1, {}});
        break;
      case K::kHomeReached:
      case K::kArrived:
        nav_.follower().leave_road();
        if (r.kind == K::kArrived) {
          reports_.add({RobotEvent::Kind::kDone, r.order_id, r.area_id, -1, {}});
        } else {
          reports_.add({RobotEvent::Kind::kHome, "", "", -1, {}});
        }
        break;
      case K::kAccepted:
      case K::kPicked:
      case K::kCancelled:
        break;
    }
  }
}

void Forklift::set_traffic_grant(const TrafficPermit& permit) {
  if (nav_.follower().grant(permit)) executor_.replan();
}

TrafficRoute Forklift::traffic_route() const {
  TrafficRoute r = nav_.follower().route();
  if (nav_.follower().on_road()) {
    r.stopped_for = nav_.safety().stopped_for(sim_.time(), sim_.estimate().position());
    r.arrival_area = arrival_area_;
  }
  return r;
}

}  // namespace fleet::robot
