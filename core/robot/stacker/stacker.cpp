#include "robot/stacker/stacker.hpp"

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

// How far a lane's heading may differ from the pallet row's for a docking run to start on it, rad.
constexpr double kLaneAlongRow = 0.35;
// A route ending within this of the stacker's own plan's end ends where the docking starts, metres.
constexpr double kSameEnd = 0.05;
// A place this far straight behind its forks, on its own line, is backed to directly (moving up
// behind a loader), where a route would take it round the loop to dock again, metres.
constexpr double kMoveUpM = 8.0;
// A route to a stand ends in its lane this far short of it, metres: room for the body to come
// onto the stand's line (off the lane's centre, beside the picker) before it stands there.
constexpr double kStandLeadM = 5.0;

NavigationParams navigation_params(const StackerConfig& c) {
  return {.grid_resolution = c.grid_resolution,
          .route_graph = c.route_graph,
          .both_ways_when_closed = false,
          // A tricycle cannot step sideways onto its docking run: its route ends on the lane along
          // the pallet row, the run starts from there.
          .routes = {.goal_heading_tolerance = kLaneAlongRow},
          .lidar = c.lidar,
          .follower = {.traffic = c.traffic, .siding_timeout = c.siding_timeout, .wait_off_road_for_room = true},
          .safety = {.safety_gap = c.safety_gap,
                     .stale_after = c.stale_after,
                     .neighbour_max_speed = c.neighbour_max_speed,
                     .scan_range = c.safety_scan_range,
                     .escape_within = 0.0,
                     .escape_speed = 0.0}};
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
      home_(home),
      footprint_{config.body.geometry.length, config.body.geometry.width},
      nav_(navigation_params(config), std::move(site), footprint_),
      body_(config.body, rear_axle_at(home, config.body.geometry)),
      rng_(seed * 0x9e3779b97f4a7c15ULL + stream) {
  estimate_ = body_.pose();
  update_centre();
  // The centre, where traffic places the robot, comes to stand on its route's end.
  config_.pursuit.stop_short = config_.body.geometry.centre_x();
}

void Stacker::update_centre() {
  truth_centre_ = geometry::body_pose_to_map(body_.pose(), {config_.body.geometry.centre_x(), 0.0, 0.0});
}

Pose2 Stacker::estimate() const {
  return geometry::body_pose_to_map(estimate_, {config_.body.geometry.centre_x(), 0.0, 0.0});
}

RobotStatus Stacker::status() const {
  const double p = config_.pose_noise.position_sigma * config_.pose_noise.position_sigma;
  const double y = config_.pose_noise.yaw_sigma * config_.pose_noise.yaw_sigma;
  return {.time = time_,
          .truth = truth_centre_,
          .estimate = estimate(),
          .covariance = {p, 0, 0, 0, p, 0, 0, 0, y},
          .localization_score = 1.0,
          .command = twist_,
          .task_state = to_string(state_),
          .detail = reports_.detail(),
          .order_id = order_id(),
          .carried_load = carried_,
          .footprint = footprint_,
          .held_by_traffic = held_by_traffic_};
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
  if (order_ && order.order_id == order_->order_id && order.kind == orders::OrderKind::kTransport) {
    // An update (VDA 5050 style) of the transport under way: where to stand with its load, or
    // its drop place; carried out once it holds the load (hold()).
    if (!order_->drop_area_id.empty()) return refuse("order " + order.order_id + " names its drop place already");
    if (order.stand) order_->stand = order.stand;
    if (!order.drop_area_id.empty()) {
      order_->drop_area_id = order.drop_area_id;
      order_->drop_area = order.drop_area;
    }
    return true;
  }
  if (order_) return refuse("busy with order " + order_->order_id);
  if (carried_ >= 0) return refuse("carries pallet " + std::to_string(carried_));
  if (const std::string no = refusal(order.kind); !no.empty()) return refuse(no);
  StackerEvent event = order.kind == orders::OrderKind::kMove ? StackerEvent::kMove : StackerEvent::kTransport;
  if (event == StackerEvent::kMove && state_ == StackerState::kIdle &&
      control::straight_behind(estimate_, rear_axle_at(order.drop_area, config_.body.geometry), kMoveUpM)) {
    event = StackerEvent::kMoveUp;
  }
  if (!next_stacker_state(state_, event)) return refuse(std::string("busy: ") + to_string(state_));
  order_ = order;
  stood_at_.reset();
  moving_up_ = event == StackerEvent::kMoveUp;
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
  if (!nav_.set_obstacle(id, enabled) || !drives_route(state_)) return false;
  need_route_ = true;
  return true;
}

void Stacker::set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph) {
  nav_.set_site(std::move(site), std::move(route_graph));
  if (drives_route(state_)) need_route_ = true;
}

void Stacker::set_traffic_grant(const TrafficPermit& permit) {
  if (permit.area != TrafficPermit::Area::kNone) {
    if ((law_ || back_) && !work_area_.empty()) {
      area_clear_ = permit.area == TrafficPermit::Area::kClear;
      if (!area_clear_) reports_.held_by_traffic(permit.blocked_by);
    }
    return;
  }
  if (nav_.follower().grant(permit) && drives_route(state_)) need_route_ = true;
}

TrafficRoute Stacker::traffic_route() const {
  TrafficRoute r = nav_.follower().route();
  if (nav_.follower().on_road()) r.stopped_for = nav_.safety().stopped_for(time_, estimate().position());
  if (nav_.follower().on_road() && !nav_.follower().in_siding()) r.arrival_area = arrival_area_;
  if (!nav_.follower().on_road() && (law_ || back_)) r.work_area = work_area_;
  if (!nav_.follower().on_road() && !law_ && !back_ && r.points.empty()) r.keep_clear = keep_clear_;
  if (nav_.follower().before_road() && !way_out_.empty()) r.work_area = way_out_;
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
  back_.reset();
  detector_.reset();
  held_by_traffic_ = false;
  blocked_ = false;
  if (drives_route(state)) {
    need_route_ = true;
    next_route_try_ = time_;
  }
  if (state == StackerState::kDocking || state == StackerState::kPlacing || state == StackerState::kParking ||
      state == StackerState::kStanding) {
    if (state != from) dock_attempts_ = 0;
    // A stand is always reached along its own line (hold, route_goal): docking onto it would
    // swing the body across the racks beside the lane.
    if (state == StackerState::kStanding || (moving_up_ && state == StackerState::kParking)) {
      start_moving_up();
    } else {
      moving_up_ = false;
      start_docking();
    }
  }
  if (state == StackerState::kLifting || state == StackerState::kLowering) forks_done_at_ = time_ + config_.lift_time;
  // Docked at a pallet place, for its forks or with its load until told where to stand, it will
  // turn out to whichever side its next route leads: over the area it docked by, or its mirror
  // image. It asks traffic to keep both clear until it sets off (note_way_out).
  if (state == StackerState::kLifting || state == StackerState::kLowering) {
    keep_clear_.clear();
    if (config_.traffic && !work_area_.empty()) keep_clear_ = with_mirror_image(work_area_, estimate_);
  } else if (state != StackerState::kHolding && !drives_route(state)) {
    keep_clear_.clear();
  }
  if (state != from) reports_.state_changed(order_id().value_or(""), to_string(state), false);
  if (phase_of(state) != from_phase && order_) reports_.phase_changed(order_->order_id, phase_of(state));
}

bool Stacker::plan_route() {
  if (auto permit = nav_.follower().take_route()) {
    // The traffic manager re-routed this robot (a way round, a siding, or back from one).
    nav_.follower().adopt_route(*permit, nav_.site().graph.graph, estimate().position());
    at_siding_end_ = false;
    note_way_out();
    nav_.safety().clear();
    reports_.set_detail(permit->siding ? "yielding on a siding" : "re-routed by traffic");
    return true;
  }
  planning::Route route = nav_.plan(estimate(), route_goal());
  if (route.status != planning::PlanStatus::kFound || route.points.size() < 2) {
    nav_.follower().drop_path();
    reports_.set_detail(route.status == planning::PlanStatus::kBlockedPartial ? "route blocked by an obstacle"
                                                                              : "no route");
    return false;
  }
  nav_.follower().adopt_plan(route);
  planned_end_ = nav_.follower().path().back();
  // Docking at a pallet place sweeps across the lane it comes along; parking in its bay off the
  // aisle it waits for its work area as it arrives, like a robot beside the roads.
  arrival_area_.clear();
  if (state_ == StackerState::kToPick || state_ == StackerState::kToDrop) {
    arrival_area_ = sweeps_.arrival(nav_.follower().path(), docking_params(), dock_prior());
  }
  at_siding_end_ = false;
  note_way_out();
  nav_.safety().clear();
  return true;
}

Pose2 Stacker::route_goal() const {
  if (state_ == StackerState::kToStand && order_ && order_->stand) {
    // The lane the stand lies in, kStandLeadM short of it: the body's centre ends there facing
    // along the lane, and drives on straight to the stand (start_moving_up).
    const Vec2 lead = order_->stand->position() - kStandLeadM * heading_of(order_->stand->yaw);
    return {lead.x, lead.y, order_->stand->yaw};
  }
  // From the body's centre (the pose the traffic manager knows) to where the rear axle starts the
  // docking; the rear axle then follows the path from its projection onto it.
  const Pose2 prior = dock_prior();
  const Vec2 goal = sweeps_.approach_of(prior);
  return {goal.x, goal.y, geometry::normalize_angle(prior.yaw + std::numbers::pi / 2)};
}

void Stacker::note_way_out() {
  // Beside the road (in a dock, in its bay) its way onto the lane sweeps across it; on the road
  // the route's places cover the body.
  constexpr double kBesideTheRoad = 0.3;  // metres of path before the road's first point
  keep_clear_.clear();
  way_out_.clear();
  if (config_.traffic && nav_.follower().road_start() > kBesideTheRoad) {
    way_out_ = sweeps_.way_out(nav_.follower().path(), estimate_, nav_.follower().road_start());
  }
}

double Stacker::clearance_ahead() const {
  // How far the stacker can drive along its path before its footprint meets another robot's
  // published one (grown by the margin and by how far it may have moved since, distance_since_seen).
  // The sweep is the pursuit rolled forward on the body model from the estimate, the wheel as it
  // stands: in a bend the real rear axle cuts inside the path and the front swings with it, so
  // bodies placed on the path at its tangent would meet a robot the stacker passes 0.4 m from.
  const std::vector<Vec2>& path = nav_.follower().path();
  if (path.size() < 2 || nav_.neighbours().empty()) return std::numeric_limits<double>::infinity();
  const geometry::Polygon here = geometry::footprint_polygon(estimate(), footprint_);
  std::vector<geometry::Polygon> others;
  for (const auto& n : nav_.neighbours()) {
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
  if (nav_.follower().path().size() < 2) {
    apply({0.0, body_.state().theta_steer});
    return;
  }
  // Measured at the centre, ahead of the rear axle: the body stops short of the grant's end.
  const double room = nav_.follower().room(estimate().position());
  const double clearance = clearance_ahead();
  const bool held = room <= 0.0 || at_siding_end_;
  const bool blocked = clearance <= 0.05;
  if (held != held_by_traffic_ || blocked != blocked_) {
    held_by_traffic_ = held;
    blocked_ = blocked;
  }
  if (nav_.follower().siding_timed_out(time_, held)) need_route_ = true;
  if (blocked) {
    const std::string ahead = nav_.safety().robot_within(estimate(), nav_.neighbours(), 1.0);
    reports_.stopped_ahead(ahead);
    nav_.safety().note(time_, estimate().position(), ahead);
  } else if (held) {
    reports_.held_by_traffic(nav_.follower().blocked_by());
  } else {
    reports_.driving_on();
  }
  const control::TricyclePursuitOutput out =
      control::pursue(estimate_, nav_.follower().path(), std::min(room, clearance), body_.state().theta_steer,
                      config_.pursuit, config_.body.geometry.wheelbase);
  if (out.arrived && (nav_.follower().in_siding() || need_route_ ||
                      geometry::distance(nav_.follower().path().back(), planned_end_) > kSameEnd)) {
    // A siding's end, or a route of the traffic manager's that ends short of its own, is no place
    // of the order: the stacker waits at a siding, held, until the manager sends it on or the
    // siding times out, and plans its way on from anywhere else, instead of docking to whatever
    // stands nearby.
    at_siding_end_ = nav_.follower().in_siding();
    if (!at_siding_end_) need_route_ = true;
    apply({0.0, body_.state().theta_steer});
    return;
  }
  if (out.arrived) {
    nav_.follower().leave_road();
    apply({0.0, body_.state().theta_steer});
    fire(StackerEvent::kRouteEnded);
    return;
  }
  apply(out.command);
}

void Stacker::hold() {
  if (!order_->drop_area_id.empty()) {
    fire(StackerEvent::kDrop);
    return;
  }
  const auto same = [](const Pose2& a, const Pose2& b) {
    return geometry::distance(a.position(), b.position()) < 1e-6 && std::abs(geometry::angle_diff(a.yaw, b.yaw)) < 1e-6;
  };
  if (!order_->stand || (stood_at_ && same(*stood_at_, *order_->stand))) return;
  // Along its own line to a stand a few metres ahead (the picker's next stop down the aisle) or
  // behind it.
  const Pose2 goal = rear_axle_at(*order_->stand, config_.body.geometry);
  // Elsewhere by road to its lane a few metres short of it (route_goal), then straight on.
  const bool on_its_line =
      control::straight_ahead(estimate_, goal, kMoveUpM) || control::straight_behind(estimate_, goal, kMoveUpM);
  fire(on_its_line ? StackerEvent::kStandBack : StackerEvent::kStand);
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
    nav_.safety().take_scan(nav_.scan(truth_centre_, estimate()));
  }
}

void Stacker::apply(const sim::TricycleCommand& wanted) {
  sim::TricycleCommand command = wanted;
  const sim::TricycleRates rates = sim::forward_kinematics(command, config_.body.geometry.wheelbase);
  const double c = config_.body.geometry.centre_x();
  const control::BodyTwist twist{rates.v, rates.yaw_rate * c, rates.yaw_rate};
  if (!(twist == control::BodyTwist{}) && nav_.safety().moves_too_close(twist, estimate(), nav_.neighbours())) {
    // The last line of defence: stand, the wheel kept where it points.
    command = {0.0, body_.state().theta_steer};
    const std::string ahead = nav_.safety().robot_within(estimate(), nav_.neighbours(), 1.0);
    nav_.safety().note(time_, estimate().position(), ahead);
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
  } else if (back_) {
    move_up();
  } else if (state_ == StackerState::kLifting || state_ == StackerState::kLowering) {
    apply({0.0, body_.state().theta_steer});
    handle_forks();
  } else if (state_ == StackerState::kHolding) {
    apply({0.0, body_.state().theta_steer});
    hold();
  } else {
    apply({0.0, body_.state().theta_steer});
  }
  time_ += step_period();
}

}  // namespace fleet::robot
