#include "robot/stacker.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "control/tricycle_sweep.hpp"
#include "planning/dynamic_grid.hpp"

namespace fleet::robot {

using geometry::Pose2;
using geometry::Vec2;

namespace {

Vec2 heading_of(double yaw) {
  return {std::cos(yaw), std::sin(yaw)};
}

// How far a lane's heading may differ from the pallet row's for a docking run to start on it, rad.
constexpr double kLaneAlongRow = 0.35;
// A route ending within this of the stacker's own plan's end ends where the docking starts, metres.
constexpr double kSameEnd = 0.05;

planning::StaticGrid make_static_grid(const StackerConfig& c, const map::SiteMap& site) {
  return planning::StaticGrid({.resolution = c.grid_resolution}, site.site, site.graph.graph);
}

}  // namespace

StackerConfig StackerConfig::for_vehicle(const vehicle::VehicleProfile& profile) {
  StackerConfig c;
  const control::TricycleDrive drive = control::tricycle_drive_for(profile);
  c.body = drive.body;
  c.pursuit = drive.pursuit;
  c.control_rate_hz = 1.0 / drive.control_period;
  return c;
}

Stacker::Stacker(const StackerConfig& config, std::shared_ptr<const map::SiteMap> site, const Pose2& home,
                 std::uint64_t seed, std::uint64_t stream)
    : config_(config),
      site_(std::move(site)),
      home_(home),
      footprint_{config.body.geometry.length, config.body.geometry.width},
      body_(config.body,
            [&] {
              const Vec2 rear = home.position() - config.body.geometry.centre_x() * heading_of(home.yaw);
              return Pose2{rear.x, rear.y, home.yaw};
            }()),
      rng_(seed * 0x9e3779b97f4a7c15ULL + stream),
      static_grid_(make_static_grid(config, *site_)),
      road_(config.route_graph ? *config.route_graph : site_->graph.graph),
      // A tricycle cannot step sideways onto its docking run: its route ends on the lane along
      // the pallet row, the run starts from there.
      routes_(road_, grid_astar_, {.goal_heading_tolerance = kLaneAlongRow}),
      grid_revision_(std::numeric_limits<std::uint64_t>::max()),
      lidar_(config.lidar),
      follower_({.traffic = config.traffic, .siding_timeout = config.siding_timeout, .wait_off_road_for_room = true}),
      safety_({.safety_gap = config.safety_gap,
               .stale_after = config.stale_after,
               .neighbour_max_speed = config.neighbour_max_speed,
               .scan_range = config.safety_scan_range,
               .escape_within = 0.0,
               .escape_speed = 0.0},
              footprint_) {
  for (const auto& o : site_->site.static_obstacles) {
    obstacles_[o.id] = o.enabled_at_start;
    static_grid_.set_obstacle_enabled(o.id, o.enabled_at_start);
  }
  estimate_ = body_.pose();
  update_centre();
  // The centre, where traffic places the robot, comes to stand on its route's end.
  config_.pursuit.stop_short = config_.body.geometry.centre_x();
  // At start, not at the first order: the planners' tables for the whole site are the bulk of
  // the agent's memory, which then stays flat while it works.
  hand_grid_to_planners();
}

void Stacker::update_centre() {
  truth_centre_ = geometry::body_pose_to_map(body_.pose(), {config_.body.geometry.centre_x(), 0.0, 0.0});
}

Pose2 Stacker::estimate() const {
  return geometry::body_pose_to_map(estimate_, {config_.body.geometry.centre_x(), 0.0, 0.0});
}

std::array<double, 9> Stacker::covariance() const {
  const double p = config_.pose_noise.position_sigma * config_.pose_noise.position_sigma;
  const double y = config_.pose_noise.yaw_sigma * config_.pose_noise.yaw_sigma;
  return {p, 0, 0, 0, p, 0, 0, 0, y};
}

std::optional<std::string> Stacker::order_id() const {
  if (order_) return order_->order_id;
  return std::nullopt;
}

std::string Stacker::refusal(orders::OrderKind kind) const {
  return kind == orders::OrderKind::kPick ? "a stacker performs no pickItem" : "";
}

bool Stacker::submit(const task::TaskOrder& order, std::string* why) {
  const auto refuse = [&](std::string text) {
    if (why) *why = std::move(text);
    return false;
  };
  if (order_) return refuse("busy with order " + order_->order_id);
  if (carried_ >= 0) return refuse("carries pallet " + std::to_string(carried_));
  if (const std::string no = refusal(order.kind); !no.empty()) return refuse(no);
  const StackerEvent event = order.kind == orders::OrderKind::kMove ? StackerEvent::kMove : StackerEvent::kTransport;
  if (!next_stacker_state(state_, event)) return refuse(std::string("busy: ") + to_string(state_));
  order_ = order;
  fire(event);
  return true;
}

bool Stacker::withdraw() {
  if (!order_) return true;
  if (!next_stacker_state(state_, StackerEvent::kCancel)) return false;
  order_.reset();
  fire(StackerEvent::kCancel);
  return true;
}

bool Stacker::set_obstacle(const std::string& id, bool enabled) {
  auto it = obstacles_.find(id);
  if (it == obstacles_.end() || it->second == enabled) return false;
  it->second = enabled;
  static_grid_.set_obstacle_enabled(id, enabled);
  if (!drives_route(state_)) return false;
  need_route_ = true;
  return true;
}

void Stacker::set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph) {
  site_ = std::move(site);
  config_.route_graph = std::move(route_graph);
  static_grid_ = make_static_grid(config_, *site_);
  obstacles_.clear();
  for (const auto& o : site_->site.static_obstacles) {
    obstacles_[o.id] = o.enabled_at_start;
    static_grid_.set_obstacle_enabled(o.id, o.enabled_at_start);
  }
  // routes_ keeps a reference to road_: assigned in place, it plans on the new graph.
  road_ = planning::RoadPlanner(config_.route_graph ? *config_.route_graph : site_->graph.graph);
  grid_revision_ = std::numeric_limits<std::uint64_t>::max();
  hand_grid_to_planners();
  follower_.forget_route();
  if (drives_route(state_)) need_route_ = true;
}

void Stacker::set_traffic_grant(const TrafficPermit& permit) {
  if (permit.area != TrafficPermit::Area::kNone) {
    if (law_ && !work_area_.empty()) {
      area_clear_ = permit.area == TrafficPermit::Area::kClear;
      if (!area_clear_) reports_.held_by_traffic(permit.blocked_by);
    }
    return;
  }
  if (follower_.grant(permit) && drives_route(state_)) need_route_ = true;
}

TrafficRoute Stacker::traffic_route() const {
  TrafficRoute r = follower_.route();
  if (follower_.on_road()) r.stopped_for = safety_.stopped_for(time_, estimate().position());
  if (follower_.on_road() && !follower_.in_siding()) r.arrival_area = arrival_area_;
  if (!follower_.on_road() && law_) r.work_area = work_area_;
  if (follower_.before_road() && !way_out_.empty()) r.work_area = way_out_;
  return r;
}

bool Stacker::fire(StackerEvent event) {
  const auto next = next_stacker_state(state_, event);
  if (!next) return false;
  enter(*next);
  return true;
}

void Stacker::enter(StackerState state) {
  const StackerState from = state_;
  const bool moving = order_ && order_->kind == orders::OrderKind::kMove;
  const auto phase_of = [&](StackerState s) {
    return moving && s == StackerState::kParking ? orders::OrderPhase::kMoving : stacker_phase(s);
  };
  const orders::OrderPhase from_phase = phase_of(from);
  state_ = state;
  law_.reset();
  detector_.reset();
  held_by_traffic_ = false;
  blocked_ = false;
  if (drives_route(state)) {
    need_route_ = true;
    next_route_try_ = time_;
  }
  if (state == StackerState::kDocking || state == StackerState::kPlacing || state == StackerState::kParking) {
    if (state != from) dock_attempts_ = 0;
    start_docking();
  }
  if (state == StackerState::kLifting || state == StackerState::kLowering) forks_done_at_ = time_ + config_.lift_time;
  if (state != from) reports_.state_changed(order_id().value_or(""), to_string(state), false);
  if (phase_of(state) != from_phase && order_) reports_.phase_changed(order_->order_id, phase_of(state));
}

void Stacker::hand_grid_to_planners() {
  // Planners cache on the grid: hand them the new one only when an obstacle changed.
  if (static_grid_.revision() == grid_revision_) return;
  auto grid = std::make_shared<const planning::OccupancyGrid>(static_grid_.grid());
  road_.set_obstacles(*grid);
  grid_astar_.set_grid(grid);
  grid_revision_ = static_grid_.revision();
}

bool Stacker::plan_route() {
  hand_grid_to_planners();
  if (auto permit = follower_.take_route()) {
    // The traffic manager re-routed this robot (a way round, a siding, or back from one).
    follower_.adopt_route(*permit, site_->graph.graph, estimate().position());
    at_siding_end_ = false;
    note_way_out();
    safety_.clear();
    reports_.set_detail(permit->siding ? "yielding on a siding" : "re-routed by traffic");
    return true;
  }
  const Pose2 prior = dock_prior();
  const Vec2 goal = approach_of(prior);
  // From the body's centre (the pose the traffic manager knows) to where the rear axle starts the
  // docking; the rear axle then follows the path from its projection onto it.
  planning::Route route =
      routes_.plan(estimate(), {goal.x, goal.y, geometry::normalize_angle(prior.yaw + std::numbers::pi / 2)});
  if (route.status != planning::PlanStatus::kFound || route.points.size() < 2) {
    follower_.drop_path();
    reports_.set_detail(route.status == planning::PlanStatus::kBlockedPartial ? "route blocked by an obstacle"
                                                                              : "no route");
    return false;
  }
  follower_.adopt_plan(route);
  planned_end_ = follower_.path().back();
  // Docking at a pallet place sweeps across the lane it comes along; parking in its bay off the
  // aisle it waits for its work area as it arrives, like a robot beside the roads.
  arrival_area_.clear();
  if (state_ == StackerState::kToPick || state_ == StackerState::kToDrop) {
    arrival_area_ = arrival_manoeuvre(follower_.path());
  }
  at_siding_end_ = false;
  note_way_out();
  safety_.clear();
  return true;
}

void Stacker::note_way_out() {
  // Beside the road (in a dock, in its bay) its way onto the lane sweeps across it; on the road
  // the route's places cover the body.
  constexpr double kBesideTheRoad = 0.3;  // metres of path before the road's first point
  way_out_.clear();
  if (config_.traffic && follower_.road_start() > kBesideTheRoad) way_out_ = way_out_area();
}

double Stacker::clearance_ahead() const {
  // How far the stacker can drive along its path before its footprint meets another robot's
  // published one (grown by the margin and by how far it may have moved since, distance_since_seen).
  // The sweep is the pursuit rolled forward on the body model from the estimate, the wheel as it
  // stands: in a bend the real rear axle cuts inside the path and the front swings with it, so
  // bodies placed on the path at its tangent would meet a robot the stacker passes 0.4 m from.
  const std::vector<Vec2>& path = follower_.path();
  if (path.size() < 2 || neighbours_.empty()) return std::numeric_limits<double>::infinity();
  const geometry::Polygon here = geometry::footprint_polygon(estimate(), footprint_);
  std::vector<geometry::Polygon> others;
  for (const auto& n : neighbours_) {
    const double moved =
        planning::distance_since_seen(n.speed, n.age, config_.stale_after, config_.neighbour_max_speed);
    geometry::Polygon p =
        geometry::footprint_polygon(n.pose, n.footprint, config_.clearance_margin + std::min(moved, 3.0));
    // Already touching where it stands: the safety stop judges that one.
    if (!geometry::convex_polygons_overlap(p, here)) others.push_back(std::move(p));
  }
  if (others.empty()) return std::numeric_limits<double>::infinity();
  const double c = config_.body.geometry.centre_x();
  sim::Tricycle ghost = body_;
  ghost.move_to(estimate_);
  Vec2 before = estimate_.position();
  double travelled = 0.0;
  // One body pose per clearance_sample at top speed.
  const double period = config_.clearance_sample / config_.pursuit.max_speed;
  for (const Pose2& rear : control::roll_forward(ghost, path, config_.pursuit, config_.body.geometry.wheelbase, period,
                                                 config_.clearance_lookahead)) {
    const geometry::Polygon swept =
        geometry::footprint_polygon(geometry::body_pose_to_map(rear, {c, 0.0, 0.0}), footprint_);
    for (const auto& o : others) {
      if (geometry::convex_polygons_overlap(swept, o)) return travelled;
    }
    travelled += geometry::distance(before, rear.position());
    before = rear.position();
  }
  return std::numeric_limits<double>::infinity();
}

void Stacker::drive() {
  if (need_route_ && time_ >= next_route_try_) {
    if (plan_route()) {
      need_route_ = false;
    } else {
      next_route_try_ = time_ + 1.0;
    }
  }
  if (follower_.path().size() < 2) {
    apply({0.0, body_.state().theta_steer});
    return;
  }
  // Measured at the centre, ahead of the rear axle: the body stops short of the grant's end.
  const double room = follower_.room(estimate().position());
  const double clearance = clearance_ahead();
  const bool held = room <= 0.0 || at_siding_end_;
  const bool blocked = clearance <= 0.05;
  if (held != held_by_traffic_ || blocked != blocked_) {
    held_by_traffic_ = held;
    blocked_ = blocked;
  }
  if (follower_.siding_timed_out(time_, held)) need_route_ = true;
  if (blocked) {
    const std::string ahead = safety_.robot_within(estimate(), neighbours_, 1.0);
    reports_.stopped_ahead(ahead);
    safety_.note(time_, estimate().position(), ahead);
  } else if (held) {
    reports_.held_by_traffic(follower_.blocked_by());
  } else {
    reports_.driving_on();
  }
  const control::TricyclePursuitOutput out =
      control::pursue(estimate_, follower_.path(), std::min(room, clearance), body_.state().theta_steer,
                      config_.pursuit, config_.body.geometry.wheelbase);
  if (out.arrived &&
      (follower_.in_siding() || need_route_ || geometry::distance(follower_.path().back(), planned_end_) > kSameEnd)) {
    // A siding's end, or a route of the traffic manager's that ends short of its own, is no place
    // of the order: the stacker waits at a siding, held, until the manager sends it on or the
    // siding times out, and plans its way on from anywhere else, instead of docking to whatever
    // stands nearby.
    at_siding_end_ = follower_.in_siding();
    if (!at_siding_end_) need_route_ = true;
    apply({0.0, body_.state().theta_steer});
    return;
  }
  if (out.arrived) {
    follower_.leave_road();
    apply({0.0, body_.state().theta_steer});
    fire(StackerEvent::kRouteEnded);
    return;
  }
  apply(out.command);
}

void Stacker::update_sensors() {
  if (time_ >= next_pose_reading_) {
    next_pose_reading_ = time_ + 1.0 / config_.pose_rate_hz;
    // While docking the law's frame must not jump: odometry alone, as in the thesis's runs.
    if (!law_) {
      std::normal_distribution<double> unit(0.0, 1.0);
      const Pose2& t = body_.pose();
      const double g = config_.pose_blend;
      estimate_.x += g * (t.x + config_.pose_noise.position_sigma * unit(rng_) - estimate_.x);
      estimate_.y += g * (t.y + config_.pose_noise.position_sigma * unit(rng_) - estimate_.y);
      estimate_.yaw = geometry::normalize_angle(
          estimate_.yaw + g * geometry::angle_diff(t.yaw + config_.pose_noise.yaw_sigma * unit(rng_), estimate_.yaw));
    }
  }
  if (time_ >= next_scan_) {
    next_scan_ = time_ + 0.1;  // the S300s' 10 Hz is plenty for the stop's horizon
    std::vector<geometry::Polygon> seen = true_neighbours_;
    for (const auto& o : site_->site.static_obstacles) {
      if (obstacles_.at(o.id)) seen.push_back(o.polygon);
    }
    planning::LidarScan scan = lidar_.scan(truth_centre_, seen);
    scan.pose = estimate();
    safety_.take_scan(scan);
  }
}

void Stacker::apply(const sim::TricycleCommand& wanted) {
  sim::TricycleCommand command = wanted;
  const sim::TricycleRates rates = sim::forward_kinematics(command, config_.body.geometry.wheelbase);
  const double c = config_.body.geometry.centre_x();
  const control::BodyTwist twist{rates.v, rates.yaw_rate * c, rates.yaw_rate};
  if (!(twist == control::BodyTwist{}) && safety_.moves_too_close(twist, estimate(), neighbours_)) {
    // The last line of defence: stand, the wheel kept where it points.
    command = {0.0, body_.state().theta_steer};
    const std::string ahead = safety_.robot_within(estimate(), neighbours_, 1.0);
    safety_.note(time_, estimate().position(), ahead);
    reports_.stopped_ahead(ahead);
  }
  if (paused_) command = {0.0, body_.state().theta_steer};
  const sim::TricycleRates done = sim::forward_kinematics(command, config_.body.geometry.wheelbase);
  twist_ = {done.v, done.yaw_rate * c, done.yaw_rate};
  const Pose2 before = body_.pose();
  body_.step(command, step_period());
  // Odometry: the wheel encoder and the steering angle sensor, each step's motion with an error
  // proportional to its length.
  Pose2 seen = geometry::map_pose_to_body(before, body_.pose());
  const double length = std::hypot(seen.x, seen.y);
  std::normal_distribution<double> unit(0.0, 1.0);
  seen.x += config_.odometry.distance_fraction * length * unit(rng_);
  seen.y += config_.odometry.distance_fraction * length * unit(rng_);
  seen.yaw += config_.odometry.yaw_per_metre * length * unit(rng_);
  estimate_ = geometry::body_pose_to_map(estimate_, seen);
  update_centre();
}

void Stacker::step() {
  update_sensors();
  if (drives_route(state_)) {
    drive();
  } else if (law_) {
    dock();
  } else if (state_ == StackerState::kLifting || state_ == StackerState::kLowering) {
    apply({0.0, body_.state().theta_steer});
    handle_forks();
  } else {
    apply({0.0, body_.state().theta_steer});
  }
  time_ += step_period();
}

}  // namespace fleet::robot
