#include "vda5050/vehicle_master.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::vda5050 {

using geometry::Pose2;
using geometry::Vec2;

namespace {

robot::TrafficFollowerParams follower_params() {
  robot::TrafficFollowerParams p;
  p.traffic = true;
  return p;
}

/// Points closer than this are one node.
constexpr double kSamePoint = 1e-6;
/// How far from where it stands a vehicle may be to start an order at its last node.
constexpr double kAtNode = 0.25;

bool at_point(const map::RoadGraph& graph, int id, Vec2 p) {
  const map::GraphPoint& g = graph.points[static_cast<std::size_t>(id)];
  return std::hypot(g.x - p.x, g.y - p.y) < kSamePoint;
}

/// A road graph point's node id: p<id>.
std::string point_node_id(int id) {
  std::string out = "p";
  out += std::to_string(id);
  return out;
}

/// A node of one route off the road graph: v<route version>-<what>.
std::string leg_node_id(std::uint64_t version, const std::string& what) {
  std::string out = "v";
  out += std::to_string(version);
  out += '-';
  out += what;
  return out;
}

}  // namespace

VehicleMaster::VehicleMaster(std::string robot_id, std::string version, std::string map_id, std::string home_id,
                             const Pose2& home, std::uint64_t first_route_version)
    : id_(std::move(robot_id)),
      version_(std::move(version)),
      map_id_(std::move(map_id)),
      home_id_(std::move(home_id)),
      home_(home),
      pose_(home),
      follower_(follower_params(), first_route_version) {}

std::string VehicleMaster::submit(const MasterOrder& order) {
  if (order_) return "busy with order " + std::to_string(order_->id);
  if (order.kind == orders::OrderKind::kPick) return "a VDA 5050 vehicle of robot type vda5050 picks no items";
  order_ = order;
  if (order.kind == orders::OrderKind::kMove) {
    phase("MOVING");
    start_leg(Stage::kToDrop, order.drop_pose, order.drop_area);
  } else {
    phase("TO_PICK");
    start_leg(Stage::kToPick, order.pick_pose, order.pick_area);
  }
  return "";
}

bool VehicleMaster::withdraw() {
  if (!order_ || carried_ >= 0) return !order_;
  order_.reset();
  if (leg_ && leg_->sent()) {
    messages_.push_back({"instantActions", instant_action_json("cancelOrder", "cancel-" + leg_->order_id(), version_)});
  }
  start_leg(Stage::kHoming, home_, "home-" + home_id_);
  return true;
}

void VehicleMaster::grant(const robot::TrafficPermit& permit) {
  // A re-route or siding: a new order along it, once the vehicle stands at its base's end.
  if (follower_.grant(permit)) needs_plan_ = true;
}

void VehicleMaster::take_state(const VehicleState& state) {
  state_ = state;
  if (state.has_position) pose_ = {state.x, state.y, state.theta};
  for (const VehicleError& e : state.errors) {
    last_error_ = e.type + (e.description.empty() ? "" : ": " + e.description);
  }
  if (state.errors.empty()) last_error_.clear();
  if (state.position_uninitialized && !init_position_sent_) {
    instant(
        "initPosition", "init",
        {{"x", home_.x}, {"y", home_.y}, {"theta", home_.yaw}, {"mapId", map_id_}, {"lastNodeId", "home-" + home_id_}});
  }
  init_position_sent_ = state.position_uninitialized;
}

void VehicleMaster::instant(const std::string& type, const std::string& tag,
                            const std::vector<std::pair<std::string, nlohmann::json>>& parameters) {
  std::string action_id = id_;
  action_id += '-';
  action_id += tag;
  action_id += '-';
  action_id += std::to_string(++instant_actions_);
  messages_.push_back({"instantActions", instant_action_json(type, action_id, version_, parameters)});
}

void VehicleMaster::request(const std::string& type) {
  instant(type, type);
}

void VehicleMaster::set_paused(bool paused) {
  if (paused == paused_) return;
  paused_ = paused;
  instant(paused ? "startPause" : "stopPause", "pause");
}

void VehicleMaster::reconnected() {
  messages_.clear();
  // A vehicle that restarted runs again: it stays paused only when told once more.
  if (paused_) instant("startPause", "pause");
  leg_.reset();
  follower_.leave_road();
  if (stage_ != Stage::kIdle) needs_plan_ = true;
}

void VehicleMaster::take_position(const VehicleState& position) {
  if (!state_ || !position.has_position) return;
  pose_ = {position.x, position.y, position.theta};
  state_->x = position.x;
  state_->y = position.y;
  state_->theta = position.theta;
  state_->speed = position.speed;
}

void VehicleMaster::start_leg(Stage stage, const Pose2& goal, std::string goal_id) {
  stage_ = stage;
  goal_ = goal;
  goal_id_ = std::move(goal_id);
  needs_plan_ = true;
  phase_at_goal_sent_ = false;
}

void VehicleMaster::phase(const std::string& name) {
  if (order_) events_.push_back({MasterEvent::Kind::kPhase, order_->id, name, "", -1, {}});
}

std::string VehicleMaster::task_state() const {
  if (paused_) return "PAUSED";  // as an agent's robot, so the operator sees it and can resume it
  switch (stage_) {
    case Stage::kIdle:
      return "IDLE";
    case Stage::kHoming:
      return held_ ? "WAITING" : "GO_HOME";
    case Stage::kToPick:
    case Stage::kToDrop:
      if (phase_at_goal_sent_) return stage_ == Stage::kToPick ? "PICK_PALLET" : "DROP_PALLET";
      return held_ ? "WAITING" : "TRACK_PATH";
  }
  return "IDLE";
}

bool VehicleMaster::vehicle_stands_ready() const {
  if (!state_ || state_->driving) return false;
  // A leg sent that the vehicle has not reported yet (nor refused): its state predates that
  // order, so it does not tell whether the vehicle stands ready; a new order sent now would
  // meet the leg running and be refused.
  if (leg_ && leg_->sent() && state_->order_id != leg_->order_id()) {
    const bool refused = std::any_of(state_->errors.begin(), state_->errors.end(), [&](const VehicleError& e) {
      return std::any_of(e.references.begin(), e.references.end(),
                         [&](const auto& r) { return r.first == "orderId" && r.second == leg_->order_id(); });
    });
    if (!refused) return false;
  }
  // Standing at the end of its base with only horizon left (or none): a new order, started at
  // that node with its sequence id, takes over. That holds also for an order the master has
  // forgotten (the vehicle was lost meanwhile, its cancelOrder never sent).
  return state_->released_nodes_left == 0;
}

void VehicleMaster::step(emulation::EmulatedRoutes& routes) {
  if (!state_ || stage_ == Stage::kIdle) return;
  if (needs_plan_) {
    if (!vehicle_stands_ready()) return;
    plan_leg(routes);
    if (needs_plan_) return;
  }
  release();
  follow_leg();
}

std::vector<OrderNode> VehicleMaster::leg_nodes(const map::RoadGraph& graph, std::vector<double>& node_s) const {
  const std::vector<Vec2>& path = follower_.path();
  const std::vector<int> road = follower_.route().points;
  std::vector<OrderNode> nodes;
  std::size_t next_road = 0;
  double s = 0.0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (i > 0) s += geometry::distance(path[i - 1], path[i]);
    if (i > 0 && geometry::distance(path[i - 1], path[i]) < kSamePoint) {
      if (next_road < road.size() && at_point(graph, road[next_road], path[i])) {
        nodes.back().id = point_node_id(road[next_road++]);
      }
      continue;
    }
    OrderNode node{"", path[i].x, path[i].y, std::nullopt, {}};
    if (next_road < road.size() && at_point(graph, road[next_road], path[i])) {
      node.id = point_node_id(road[next_road++]);
    } else if (i + 1 == path.size()) {
      node.id = goal_id_;
    } else {
      node.id = leg_node_id(follower_.version(), std::to_string(i));
    }
    nodes.push_back(std::move(node));
    node_s.push_back(s);
  }
  // The first node is where the vehicle stands: its last node when it is there.
  if (state_ && !state_->last_node_id.empty() &&
      geometry::distance(Vec2{state_->x, state_->y}, Vec2{nodes.front().x, nodes.front().y}) < kAtNode) {
    nodes.front().id = state_->last_node_id;
  } else if (nodes.front().id.rfind('p', 0) != 0) {
    nodes.front().id = leg_node_id(follower_.version(), "start");
  }
  OrderNode& goal = nodes.back();
  goal.id = goal_id_;
  goal.theta = goal_.yaw;
  if (order_ && stage_ != Stage::kHoming && order_->kind != orders::OrderKind::kMove) {
    const bool picking = stage_ == Stage::kToPick;
    const std::string load = std::to_string(picking ? order_->load_id : carried_);
    goal.actions.push_back({picking ? "pick" : "drop",
                            std::to_string(order_->id) + (picking ? "-pick" : "-drop"),
                            "HARD",
                            {{"stationType", "floor"}, {"loadType", "EPAL"}, {"loadId", load}}});
  }
  return nodes;
}

void VehicleMaster::plan_leg(emulation::EmulatedRoutes& routes) {
  if (auto permit = follower_.take_route()) {
    follower_.adopt_route(*permit, routes.graph(), pose_.position());
  } else {
    const planning::Route route = routes.plan(pose_, goal_);
    if (route.status != planning::PlanStatus::kFound || route.points.size() < 2) {
      fail("no way from (" + std::to_string(pose_.x) + ", " + std::to_string(pose_.y) + ") to " + goal_id_ +
           " on the site's roads");
      return;
    }
    follower_.adopt_plan(route);
  }
  needs_plan_ = false;
  std::vector<double> node_s;
  std::vector<OrderNode> nodes = leg_nodes(routes.graph(), node_s);
  const std::string order_id = (order_ ? std::to_string(order_->id) : id_ + "-home") + "-" + std::to_string(++legs_);
  // A vehicle still in an order (waiting at its base's end) takes a new one only when it starts at
  // the node it stands on with that node's sequence id [VDA 5050, section 6.6.2].
  const bool at_last_node = nodes.front().id == state_->last_node_id;
  const std::uint32_t first_sequence = at_last_node ? state_->last_node_sequence_id : 0;
  leg_.emplace(order_id, map_id_, version_, std::move(nodes), std::move(node_s), first_sequence);
}

void VehicleMaster::release() {
  if (!leg_) return;
  held_ = follower_.room(pose_.position()) <= 0.0 && !state_->driving;
  // The grant's end along the leg's path, where the vehicle stands or not: the nodes up to it.
  const std::optional<double> granted = follower_.granted_end();
  if (!granted) return;  // no grant yet for this route
  if (auto message = leg_->release(*granted)) messages_.push_back({"order", order_json(*message)});
}

void VehicleMaster::follow_leg() {
  if (!leg_ || !leg_->sent()) return;
  const VehicleState& s = *state_;
  for (const VehicleError& e : s.errors) {
    for (const auto& [key, value] : e.references) {
      if (key == "orderId" && value == leg_->order_id() &&
          std::find(reported_errors_.begin(), reported_errors_.end(), value) == reported_errors_.end()) {
        reported_errors_.push_back(value);
        fail("vehicle refused VDA 5050 order " + value + ": " + e.type +
             (e.description.empty() ? "" : " (" + e.description + ")"));
        return;
      }
    }
  }
  const auto action = leg_->goal_action(s);
  if (action && (action->status == "RUNNING" || action->status == "INITIALIZING") && !phase_at_goal_sent_) {
    phase_at_goal_sent_ = true;
    phase(stage_ == Stage::kToPick ? "PICKING" : "DROPPING");
  }
  if (action && action->status == "FAILED") {
    fail("vehicle's " + action->type + " failed" + (action->result.empty() ? "" : ": " + action->result));
    return;
  }
  if (!leg_->finished_by(s)) return;
  if (!leg_->nodes().back().actions.empty() && (!action || action->status != "FINISHED")) return;
  arrived();
}

void VehicleMaster::arrived() {
  held_ = false;
  follower_.leave_road();
  leg_.reset();
  switch (stage_) {
    case Stage::kToPick:
      carried_ = order_->load_id;
      phase("TO_DROP");
      start_leg(Stage::kToDrop, order_->drop_pose, order_->drop_area);
      return;
    case Stage::kToDrop:
      if (order_->kind == orders::OrderKind::kMove) {
        events_.push_back({MasterEvent::Kind::kDone, order_->id, "", "", -1, {}});
        order_.reset();
        home_ = pose_;  // a move order parks the vehicle there
        home_id_ = goal_id_;
        stage_ = Stage::kIdle;
        return;
      }
      events_.push_back({MasterEvent::Kind::kDone, order_->id, "", "", carried_, order_->drop_pose});
      carried_ = -1;
      order_.reset();
      start_leg(Stage::kHoming, home_, "home-" + home_id_);
      return;
    case Stage::kHoming:
      stage_ = Stage::kIdle;
      return;
    case Stage::kIdle:
      return;
  }
}

void VehicleMaster::fail(const std::string& reason) {
  if (order_) events_.push_back({MasterEvent::Kind::kFailed, order_->id, "", reason, -1, {}});
  order_.reset();
  leg_.reset();
  needs_plan_ = false;
  follower_.leave_road();
  stage_ = Stage::kIdle;
}

std::vector<Outgoing> VehicleMaster::take_messages() {
  std::vector<Outgoing> out;
  out.swap(messages_);
  return out;
}

std::vector<MasterEvent> VehicleMaster::take_events() {
  std::vector<MasterEvent> out;
  out.swap(events_);
  return out;
}

}  // namespace fleet::vda5050
