#include "agent/vda5050_vehicle.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "robot/robot_factory.hpp"
#include "vda5050/factsheet.hpp"

namespace fleet::agent {

using nlohmann::json;
using vda5050::VehicleError;

namespace {
constexpr double kMaxSleepWall = 0.02;  // the loop's longest sleep between control steps
constexpr std::size_t kErrorsKept = 10;
constexpr double kMinStatePeriodWall = 0.05;  // events closer together share one state message

double unix_now() {
  return SimClock::wall_now();
}

/// The robot's own configuration with traffic control on: the order's base end holds it as a
/// traffic grant would (vda5050::VehicleDrive).
config::FleetConfig with_base_as_grant(config::FleetConfig config) {
  config.settings.set("traffic.enabled", "true", "VDA 5050 vehicle mode: the order's base is the robot's grant");
  return config;
}

}  // namespace

Vda5050Vehicle::Vda5050Vehicle(VehicleOptions options, Logger log)
    : options_(std::move(options)), log_(std::move(log)), clock_(options_.time_scale) {
  options_.config = with_base_as_grant(std::move(options_.config));
  const auto robot = options_.config.find_robot(options_.robot_id);
  fleet_ = robot->first;
  robot_ = robot::make_robot(*fleet_, options_.config, options_.site,
                             options_.site->site.find_home(robot->second->home)->pose, options_.seed,
                             robot::noise_stream_of(options_.robot_id));
  int next_load = 1;
  for (const map::LoadingArea& area : options_.site->site.loading_areas) {
    if (area.pallet_at_start) standing_loads_[next_load++] = area.pose;
  }
  robot_->set_standing_loads(standing_loads_);
  const vda5050::VehicleAddress& a = options_.address;
  json will = vda5050::header(a, 0, unix_now());
  will["connectionState"] = "CONNECTIONBROKEN";
  std::string client_id = "fleet-agent-";
  client_id += a.serial_number;
  client_id += '-';
  client_id += std::to_string(getpid());
  mqtt_ = std::make_unique<mqtt_link::MqttLink>(
      options_.broker, client_id,
      std::vector<std::string>{vda5050::topic(a, "order"), vda5050::topic(a, "instantActions")},
      mqtt_link::LastWill{vda5050::topic(a, "connection"), will.dump()});
  log_->info("{} of fleet '{}' as VDA 5050 vehicle {}/{} ({} {}) on broker {}, site '{}'", fleet_->robot_type,
             fleet_->id, a.manufacturer, a.serial_number, a.interface_name, a.version, options_.broker,
             options_.site->site.name);
}

void Vda5050Vehicle::publish(const std::string& name, const json& body, int qos, bool retained) {
  mqtt_->publish(vda5050::topic(options_.address, name), body.dump(), qos, retained);
}

void Vda5050Vehicle::publish_connection(const std::string& state) {
  json message = vda5050::header(options_.address, ++header_ids_["connection"], unix_now());
  message["connectionState"] = state;
  publish("connection", message, 1, true);
}

void Vda5050Vehicle::publish_factsheet() {
  publish("factsheet",
          vda5050::factsheet_json(options_.address, fleet_->profile, options_.config.top_speed(*fleet_),
                                  ++header_ids_["factsheet"], unix_now()),
          0, true);
}

json Vda5050Vehicle::position_json() const {
  const robot::RobotStatus status = robot_->status();
  return {{"x", status.estimate.x},       {"y", status.estimate.y},
          {"theta", status.estimate.yaw}, {"mapId", options_.site->site.name},
          {"positionInitialized", true},  {"localizationScore", std::clamp(status.localization_score, 0.0, 1.0)}};
}

void Vda5050Vehicle::publish_state() {
  const robot::RobotStatus status = robot_->status();
  json message = vda5050::header(options_.address, ++header_ids_["state"], unix_now());
  message["orderId"] = order_.order_id();
  message["orderUpdateId"] = order_.update_id();
  message["lastNodeId"] = order_.last_node_id();
  message["lastNodeSequenceId"] = order_.last_node_sequence();
  message["nodeStates"] = order_.node_states();
  message["edgeStates"] = order_.edge_states();
  message["actionStates"] = order_.action_states_json();
  message["driving"] = last_driving_;
  message["paused"] = paused_;
  message["operatingMode"] = "AUTOMATIC";
  // The simulated robot has no battery model: always full, never charging.
  message["batteryState"] = {{"batteryCharge", 100.0}, {"charging", false}};
  message["safetyState"] = {{"eStop", "NONE"}, {"fieldViolation", false}};
  json errors = json::array();
  for (const VehicleError& e : errors_) errors.push_back(vda5050::error_json(e));
  message["errors"] = errors;
  message["agvPosition"] = position_json();
  message["velocity"] = {{"vx", status.command.vx}, {"vy", status.command.vy}, {"omega", status.command.omega}};
  json loads = json::array();
  if (status.carried_load >= 0) {
    loads.push_back({{"loadId", std::to_string(status.carried_load)}, {"loadType", fleet_->profile.load.load_type}});
  }
  message["loads"] = loads;
  publish("state", message);
  last_state_wall_ = SimClock::wall_now();
  state_due_ = false;
}

void Vda5050Vehicle::publish_visualization() {
  const robot::RobotStatus status = robot_->status();
  json message = vda5050::header(options_.address, ++header_ids_["visualization"], unix_now());
  message["agvPosition"] = position_json();
  message["velocity"] = {{"vx", status.command.vx}, {"vy", status.command.vy}, {"omega", status.command.omega}};
  publish("visualization", message);
  last_visualization_wall_ = SimClock::wall_now();
}

void Vda5050Vehicle::reject(const VehicleError& error) {
  log_->warn("{}: {}", error.type, error.description);
  errors_.push_back(error);
  if (errors_.size() > kErrorsKept) errors_.erase(errors_.begin());
  state_due_ = true;
}

void Vda5050Vehicle::handle_messages() {
  for (const mqtt_link::MqttMessage& m : mqtt_->take()) {
    json message = json::parse(m.payload, nullptr, false);
    const bool is_order = m.topic.ends_with("/order");
    if (message.is_discarded()) {
      // Not JSON at all: nothing to refer to but the topic.
      reject({"validationError",
              "WARNING",
              "the message on " + m.topic + " is not JSON",
              {{"topic", is_order ? "order" : "instantActions"}}});
      continue;
    }
    if (is_order) {
      on_order(message);
    } else {
      on_instant_actions(message);
    }
  }
}

void Vda5050Vehicle::on_order(const json& message) {
  vda5050::ReceivedOrder received;
  try {
    received = vda5050::read_order(message);
  } catch (const vda5050::MessageError& e) {
    reject(vda5050::order_error("validationError", std::string("invalid order: ") + e.what(), message));
    return;
  }
  const map::SiteMap& site = *options_.site;
  bool at_first_node = false;
  std::string why;
  if (const auto first = vda5050::locate_node(received.nodes.front(), site.site, site.graph.graph, &why)) {
    const double deviation = received.nodes.front().allowed_deviation;
    const double tolerance = deviation > 0.0 ? deviation : fleet_->footprint.length;
    at_first_node = geometry::distance(robot_->status().estimate.position(), first->pose.position()) <= tolerance;
  }
  const vda5050::OrderVerdict verdict = order_.check(received, message, at_first_node);
  if (verdict.error) return reject(*verdict.error);
  const vda5050::OrderIntake intake = *verdict.intake;
  if (intake == vda5050::OrderIntake::kRepeat) {
    state_due_ = true;
    return;
  }
  if (intake == vda5050::OrderIntake::kNew && !received.nodes.front().actions.empty()) {
    const vda5050::ReceivedAction& a = received.nodes.front().actions.front();
    return reject(vda5050::order_error("orderError",
                                       "actions on the first node: Fleet's robots act where they drive to", message,
                                       {{"actionId", a.id}, {"actionType", a.type}}));
  }
  const bool under_way = job_ && intake != vda5050::OrderIntake::kNew;
  const auto job = vda5050::job_of(received.order_id, order_.nodes_taking(received, intake), received.edges, site.site,
                                   site.graph.graph, robot_->refusal(orders::OrderKind::kTransport).empty(),
                                   job_ && picked_, message);
  if (const auto* error = std::get_if<VehicleError>(&job)) return reject(*error);
  if (const auto error = take_job(std::get<vda5050::VehicleJob>(job), under_way, message)) return reject(*error);
  // Order warnings stand until an order is accepted [VDA 5050, section 6.6.4].
  std::erase_if(errors_, [](const VehicleError& e) { return e.type != "orderActionError"; });
  order_.take(received, intake);
  // Updates come with every grant that reaches further: the new orders at info, the rest at debug.
  log_->log(intake == vda5050::OrderIntake::kNew ? spdlog::level::info : spdlog::level::debug,
            "order {} update {} taken ({}): base to node '{}'", received.order_id, received.update_id,
            intake == vda5050::OrderIntake::kNew      ? "new"
            : intake == vda5050::OrderIntake::kUpdate ? "update"
                                                      : "stitched",
            order_.base_end().id);
  update_leg();
  state_due_ = true;
}

std::optional<VehicleError> Vda5050Vehicle::take_job(const vda5050::VehicleJob& next, bool under_way,
                                                     const json& message) {
  const auto error = [&](const char* type, const std::string& why) { return vda5050::order_error(type, why, message); };
  // The drop of a transport whose pick came alone (picked, or still on the way to it).
  const bool names_the_drop = job_ && job_->order.kind == orders::OrderKind::kTransport && job_->drop_action.empty() &&
                              !next.drop_action.empty() &&
                              (next.pick_action == job_->pick_action || (picked_ && next.pick_action.empty()));
  const bool same_job = under_way && next.goal_node == job_->goal_node && next.drop_action == job_->drop_action &&
                        (picked_ || next.pick_action == job_->pick_action);
  if (names_the_drop) {
    if (!robot_->set_drop(next.order.drop_area_id, next.order.drop_area)) {
      return error("orderError", "this robot takes a pick and its drop only in one order");
    }
    job_->drop_action = next.drop_action;
    job_->order.drop_area_id = next.order.drop_area_id;
    job_->order.drop_area = next.order.drop_area;
    job_->goal_node = next.goal_node;
  } else if (!same_job) {
    if (picked_ && job_) {
      return error("orderError", "the robot carries a load: its next order drops it");
    }
    if (under_way && job_->order.kind != orders::OrderKind::kMove) {
      return error("orderUpdateError", "the update changes the transport under way");
    }
    if (job_ && !robot_->withdraw()) return error("orderError", "the robot cannot leave the job under way now");
    job_.reset();
    std::string why;
    if (!robot_->submit(next.order, &why)) return error("orderError", "the robot cannot take the order now: " + why);
    job_ = next;
    picked_ = false;
    drive_ = vda5050::VehicleDrive{};
    return std::nullopt;
  }
  job_->nodes = next.nodes;
  job_->order.order_id = next.order.order_id;
  return std::nullopt;
}

void Vda5050Vehicle::update_leg() {
  if (!job_) {
    drive_.set_leg({});
    return;
  }
  const bool to_goal = picked_ || job_->order.kind != orders::OrderKind::kTransport || job_->pick_action.empty();
  const std::uint32_t leg_end = to_goal ? job_->goal_node : job_->pick_node;
  std::vector<vda5050::NodeOnSite> leg;
  for (const vda5050::NodeOnSite& node : job_->nodes) {
    if (node.sequence > order_.last_node_sequence() && node.sequence <= leg_end) leg.push_back(node);
  }
  drive_.set_leg(std::move(leg));
}

void Vda5050Vehicle::drive() {
  const robot::TrafficRoute route = robot_->traffic_route();
  std::optional<robot::TrafficPermit> permit;
  if (job_) permit = drive_.permit(route, options_.site->graph.graph);
  if (!permit) {
    permit = robot::TrafficPermit{};
    permit->version = route.version;
    permit->granted_index = -1;  // stands where it is: the base reaches no further
  }
  robot_->set_traffic_grant(*permit);
  bool passed_any = false;
  for (const std::uint32_t sequence : drive_.passed(route)) {
    if (sequence <= order_.last_node_sequence()) continue;
    order_.passed(sequence);
    passed_any = true;
  }
  if (passed_any) {
    update_leg();
    state_due_ = true;
  }
}

void Vda5050Vehicle::on_phase(const std::string& phase) {
  if (!job_) return;
  log_->info("order {}: {}", order_.order_id(), phase);
  if ((phase == "SEARCHING" || phase == "PICKING") && !picked_ && !job_->pick_action.empty()) {
    if (job_->pick_node > order_.last_node_sequence()) order_.passed(job_->pick_node);
    order_.set_action_status(job_->pick_action, "RUNNING");
  } else if (phase == "DROPPING" && !job_->drop_action.empty()) {
    if (job_->goal_node > order_.last_node_sequence()) order_.passed(job_->goal_node);
    order_.set_action_status(job_->drop_action, "RUNNING");
  }
  state_due_ = true;
}

void Vda5050Vehicle::handle_events() {
  using K = robot::RobotEvent::Kind;
  for (const robot::RobotEvent& e : robot_->take_events()) {
    switch (e.kind) {
      case K::kPhase:
        on_phase(e.text);
        break;
      case K::kLifted:
        standing_loads_.erase(e.load_id);
        robot_->set_standing_loads(standing_loads_);
        log_->info("load {} taken up", e.load_id);
        if (job_ && !job_->pick_action.empty()) {
          order_.set_action_status(job_->pick_action, "FINISHED");
          picked_ = true;
          update_leg();
        }
        state_due_ = true;
        break;
      case K::kDone:
        if (e.load_id >= 0) {
          standing_loads_[e.load_id] = e.load_pose;
          robot_->set_standing_loads(standing_loads_);
        }
        if (!job_) break;
        if (job_->goal_node > order_.last_node_sequence()) order_.passed(job_->goal_node);
        if (!job_->drop_action.empty()) order_.set_action_status(job_->drop_action, "FINISHED");
        log_->info("order {}: done at node {}", order_.order_id(), order_.last_node_id());
        job_.reset();
        picked_ = false;
        update_leg();
        state_due_ = true;
        break;
      case K::kAreaEmpty:
      case K::kFailed:
        if (!job_) break;
        for (const std::string& action : {job_->pick_action, job_->drop_action}) {
          if (action.empty()) continue;
          order_.set_action_status(action, "FAILED", e.text);
        }
        reject({"orderActionError",
                "WARNING",
                e.text.empty() ? "the pick found no load" : e.text,
                {{"topic", "order"}, {"orderId", order_.order_id()}}});
        job_.reset();
        picked_ = false;
        update_leg();
        break;
      case K::kHome:
      case K::kState:
        break;
    }
  }
}

void Vda5050Vehicle::on_instant_actions(const json& message) {
  std::vector<vda5050::ReceivedAction> actions;
  try {
    actions = vda5050::read_instant_actions(message);
  } catch (const vda5050::MessageError& e) {
    VehicleError error{"validationError",
                       "WARNING",
                       std::string("invalid instant actions: ") + e.what(),
                       {{"topic", "instantActions"}}};
    if (message.is_object() && message.contains("headerId")) {
      error.references.emplace_back("headerId", message["headerId"].dump());
    }
    return reject(error);
  }
  for (const vda5050::ReceivedAction& action : actions) instant_action(action);
  state_due_ = true;
}

void Vda5050Vehicle::instant_action(const vda5050::ReceivedAction& action) {
  const std::vector<std::pair<std::string, std::string>> refs{
      {"topic", "instantActions"}, {"actionId", action.id}, {"actionType", action.type}};
  std::string status = "FINISHED";
  std::string result;
  if (action.type == "cancelOrder") {
    if (!order_.active()) {
      reject({"noOrderToCancel", "WARNING", "cancelOrder: the vehicle has no order", refs});
      status = "FAILED";
    } else if (job_ && !robot_->withdraw()) {
      result = "the load is half taken up: the robot carries the job on";
      status = "FAILED";
    } else {
      order_.cancel();
      job_.reset();
      update_leg();
      log_->warn("order {} cancelled by the master", order_.order_id());
    }
  } else if (action.type == "startPause" || action.type == "stopPause") {
    paused_ = action.type == "startPause";
    robot_->set_paused(paused_);
  } else if (action.type == "stateRequest") {
    state_due_ = true;
  } else if (action.type == "factsheetRequest") {
    publish_factsheet();
  } else {
    reject({"instantActionError", "WARNING", "instant action '" + action.type + "' is not one this vehicle performs",
            refs});
    status = "FAILED";
  }
  order_.add_instant_action({action.id, action.type, status, result});
}

void Vda5050Vehicle::run(const std::atomic<bool>& stop) {
  const double step = robot_->step_period();
  double offset = clock_.now() - robot_->time();
  while (!stop.load()) {
    const double until_step_wall = clock_.to_wall(robot_->time() + offset + step - clock_.now());
    std::this_thread::sleep_for(std::chrono::duration<double>(std::clamp(until_step_wall, 0.0, kMaxSleepWall)));
    if (mqtt_->connections() != connections_seen_) {
      // A new session: the broker forgot nothing retained, but a master may have seen the will.
      connections_seen_ = mqtt_->connections();
      log_->info("connected to {}", options_.broker);
      publish_connection("ONLINE");
      publish_factsheet();
      state_due_ = true;
    }
    handle_messages();
    double behind = clock_.now() - (robot_->time() + offset);
    if (behind > 1.0) {
      offset += behind - step;
      behind = step;
    }
    drive();
    for (; behind >= step; behind -= step) {
      robot_->step();
      handle_events();
    }
    const control::BodyTwist twist = robot_->status().command;
    const bool driving = std::abs(twist.vx) + std::abs(twist.vy) + std::abs(twist.omega) > 1e-3;
    if (driving != last_driving_) {
      last_driving_ = driving;
      state_due_ = true;
    }
    const double now_wall = SimClock::wall_now();
    if ((state_due_ && now_wall - last_state_wall_ >= kMinStatePeriodWall) ||
        now_wall - last_state_wall_ >= options_.state_period_s) {
      publish_state();
    }
    if (now_wall - last_visualization_wall_ >= options_.visualization_period_s) publish_visualization();
  }
  publish_connection("OFFLINE");
  log_->info("stopping");
}

}  // namespace fleet::agent
