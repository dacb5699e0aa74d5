#include "emulation/emulated_robot.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::emulation {

using geometry::Pose2;
using geometry::Vec2;

planning::GridPath StraightLegs::plan(Vec2 start, Vec2 goal, const planning::PlanOptions&) {
  planning::GridPath path;
  path.status = planning::PlanStatus::kFound;
  path.points = {start, goal};
  path.length = geometry::distance(start, goal);
  return path;
}

EmulatedRoutes::EmulatedRoutes(std::shared_ptr<const map::RoadGraph> graph)
    : graph_(std::move(graph)), road_(*graph_), routes_(road_, legs_) {}

planning::Route EmulatedRoutes::plan(const Pose2& from, const Pose2& to) {
  return routes_.plan(from, to);
}

namespace {

std::vector<double> cumulative(const std::vector<Vec2>& points) {
  std::vector<double> cum(points.size(), 0.0);
  for (std::size_t i = 1; i < points.size(); ++i) cum[i] = cum[i - 1] + geometry::distance(points[i - 1], points[i]);
  return cum;
}

robot::TrafficFollowerParams follower_params(const EmulationParams& params) {
  robot::TrafficFollowerParams p;
  p.traffic = true;
  p.siding_timeout = params.siding_timeout_s;
  return p;
}

}  // namespace

EmulatedRobot::EmulatedRobot(std::string id, const Pose2& home, const EmulationParams& params,
                             std::uint64_t first_route_version)
    : id_(std::move(id)),
      home_(home),
      params_(params),
      pose_(home),
      follower_(follower_params(params), first_route_version) {}

std::string EmulatedRobot::submit(const EmulatedOrder& order) {
  if (order_) return "busy with order " + std::to_string(order_->id);
  if (order.kind == orders::OrderKind::kPick) return "an emulated robot picks no items";
  order_ = order;
  events_.push_back(
      {EmulatedEvent::Kind::kPhase, order.id, order.kind == orders::OrderKind::kMove ? "MOVING" : "TO_PICK", -1, {}});
  if (order.kind == orders::OrderKind::kMove) {
    start_leg(Stage::kToDrop, order.drop_pose);
  } else {
    start_leg(Stage::kToPick, order.pick_pose);
  }
  return "";
}

bool EmulatedRobot::withdraw() {
  if (!order_ || carried_ >= 0) return !order_;
  order_.reset();
  start_leg(Stage::kHoming, home_);
  return true;
}

void EmulatedRobot::grant(const robot::TrafficPermit& permit) {
  // A re-route or siding from the manager: taken at the next plan, as an agent does.
  if (follower_.grant(permit)) needs_plan_ = true;
}

void EmulatedRobot::start_leg(Stage stage, const Pose2& goal) {
  stage_ = stage;
  goal_ = goal;
  needs_plan_ = true;
  plan_after_ = 0.0;
}

void EmulatedRobot::phase(const std::string& name) {
  if (order_) events_.push_back({EmulatedEvent::Kind::kPhase, order_->id, name, -1, {}});
}

std::string EmulatedRobot::task_state() const {
  switch (stage_) {
    case Stage::kIdle:
      return "IDLE";
    case Stage::kPicking:
      return "PICK_PALLET";
    case Stage::kDropping:
      return "DROP_PALLET";
    case Stage::kHoming:
      return held_ ? "WAITING" : "GO_HOME";
    case Stage::kToPick:
    case Stage::kToDrop:
      return held_ ? "WAITING" : "TRACK_PATH";
  }
  return "IDLE";
}

void EmulatedRobot::step(double now, EmulatedRoutes& routes) {
  speed_ = 0.0;
  if (stage_ == Stage::kPicking || stage_ == Stage::kDropping) {
    if (now >= dwell_until_) arrived(now);
    return;
  }
  if (stage_ == Stage::kIdle) return;
  if (needs_plan_ && now >= plan_after_) {
    if (auto permit = follower_.take_route()) {
      follower_.adopt_route(*permit, routes.graph(), pose_.position());
    } else {
      const planning::Route route = routes.plan(pose_, goal_);
      if (route.status != planning::PlanStatus::kFound || route.points.size() < 2) {
        plan_after_ = now + params_.retry_s;
        return;
      }
      follower_.adopt_plan(route);
    }
    needs_plan_ = false;
    path_cum_ = cumulative(follower_.path());
    path_s_ = 0.0;
  }
  if (!needs_plan_) drive(now);
}

void EmulatedRobot::drive(double now) {
  const std::vector<Vec2>& path = follower_.path();
  if (path.size() < 2) {
    arrived(now);
    return;
  }
  const double room = follower_.room(pose_.position());
  held_ = room <= 0.0;
  if (follower_.siding_timed_out(now, held_)) {
    needs_plan_ = true;  // left the siding: its own way on
    return;
  }
  const double total = path_cum_.back();
  const double step = std::min({params_.speed * params_.step_s, std::max(0.0, room), total - path_s_});
  if (step > 0.0) {
    path_s_ += step;
    speed_ = step / params_.step_s;
    const auto next = std::upper_bound(path_cum_.begin(), path_cum_.end(), path_s_);
    const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(next - path_cum_.begin()), path.size() - 1);
    const Vec2 a = path[i - 1];
    const Vec2 b = path[i];
    const double length = path_cum_[i] - path_cum_[i - 1];
    const double t = length > 0.0 ? (path_s_ - path_cum_[i - 1]) / length : 1.0;
    pose_.x = a.x + (b.x - a.x) * t;
    pose_.y = a.y + (b.y - a.y) * t;
    if (length > 1e-9) pose_.yaw = std::atan2(b.y - a.y, b.x - a.x);
  }
  if (path_s_ >= total - 1e-9) arrived(now);
}

void EmulatedRobot::arrived(double now) {
  held_ = false;
  switch (stage_) {
    case Stage::kToPick:
      follower_.leave_road();
      stage_ = Stage::kPicking;
      dwell_until_ = now + params_.dwell_s;
      phase("PICKING");
      return;
    case Stage::kPicking:
      carried_ = order_->load_id;
      phase("TO_DROP");
      start_leg(Stage::kToDrop, order_->drop_pose);
      return;
    case Stage::kToDrop:
      follower_.leave_road();
      if (order_->kind == orders::OrderKind::kMove) {
        events_.push_back({EmulatedEvent::Kind::kDone, order_->id, "", -1, {}});
        order_.reset();
        home_ = pose_;  // a move order parks the robot there
        stage_ = Stage::kIdle;
        return;
      }
      stage_ = Stage::kDropping;
      dwell_until_ = now + params_.dwell_s;
      phase("DROPPING");
      return;
    case Stage::kDropping:
      events_.push_back({EmulatedEvent::Kind::kDone, order_->id, "", carried_, order_->drop_pose});
      carried_ = -1;
      order_.reset();
      start_leg(Stage::kHoming, home_);
      return;
    case Stage::kHoming:
      follower_.leave_road();
      stage_ = Stage::kIdle;
      events_.push_back({EmulatedEvent::Kind::kHome, 0, "", -1, {}});
      return;
    case Stage::kIdle:
      return;
  }
}

std::vector<EmulatedEvent> EmulatedRobot::take_events() {
  std::vector<EmulatedEvent> out;
  out.swap(events_);
  return out;
}

}  // namespace fleet::emulation
