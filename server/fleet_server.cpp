#include "server/fleet_server.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include "common/process_memory.hpp"
#include "model/names.hpp"
#include "monitor/order_accounting.hpp"
#include "orders/order_request_check.hpp"
#include "traffic/traffic_settings.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderPhase;
using orders::OrderStatus;
using orders::TransitionResult;

namespace {
constexpr double kReplyRetentionWallS = 30.0;  // a requester has this long to read its reply
constexpr double kMaxRoutingHzWall = 100.0;    // FleetView is capped in wall rate at high time scales

model::OrderInfo info_of(const Order& o) {
  std::vector<model::OrderEvent> history;
  for (const auto& e : o.history) {
    history.push_back({e.sim_time, std::string(orders::to_string(e.status)), std::string(orders::to_string(e.phase)),
                       e.robot_id, e.reason, e.robot_x, e.robot_y});
  }
  return {o.id,
          o.request_id,
          o.pick_area,
          o.drop_area,
          o.fleet_id,
          o.robot_id,
          std::string(orders::to_string(o.status)),
          std::string(orders::to_string(o.phase)),
          o.reason,
          o.priority,
          o.created_sim,
          o.updated_sim,
          std::move(history),
          std::string(orders::to_string(o.kind))};
}

/// Searching or picking: the robot stands at the pick area, the pallet perhaps on its way up.
bool at_pick_area(OrderPhase phase) {
  return phase == OrderPhase::kSearching || phase == OrderPhase::kPicking;
}

/// Driving to the drop or putting the pallet down: it was lifted.
bool past_the_lift(OrderPhase phase) {
  return phase == OrderPhase::kToDrop || phase == OrderPhase::kDropping;
}
}  // namespace

FleetServer::FleetServer(ServerOptions options, Logger log)
    : options_(std::move(options)),
      log_(std::move(log)),
      store_(options_.db_path),
      travel_(options_.site_map->graph.graph),
      clock_(options_.time_scale),
      rng_(options_.seed),
      policy_(orders::make_dispatch_policy(options_.config.settings.get_string("server.dispatch_policy"))),
      auto_orders_(options_.config.settings.get_bool("server.auto_orders")),
      participant_(options_.domain),
      server_info_writer_(participant_, dds::qos::latched_state()),
      reply_writer_(participant_, dds::qos::latched_state()),
      order_writer_(participant_, dds::qos::latched_state()),
      order_info_writer_(participant_, dds::qos::latched_state()),
      map_writer_(participant_, dds::qos::latched_state()),
      control_writer_(participant_, dds::qos::latched_state()),
      pallet_writer_(participant_, dds::qos::latched_state()),
      obstacle_writer_(participant_, dds::qos::latched_state()),
      fleet_view_writer_(participant_, dds::qos::live_state()),
      request_reader_(participant_, dds::qos::requests()),
      command_reader_(participant_, dds::qos::requests()),
      robot_state_reader_(participant_, dds::qos::robot_state()),
      robot_path_reader_(participant_, dds::qos::live_state()),
      truth_reader_(participant_, dds::qos::live_state()),
      order_report_reader_(participant_, dds::qos::latched_state()),
      waitset_(participant_) {
  reset_obstacles();
  for (dds_entity_t reader : {request_reader_.handle(), command_reader_.handle(), robot_state_reader_.handle(),
                              robot_path_reader_.handle(), order_report_reader_.handle()}) {
    waitset_.attach(reader);
  }
  if (options_.config.settings.get_bool("traffic.enabled")) {
    traffic_ = std::make_unique<TrafficControl>(options_.site_map->graph.graph,
                                                traffic::configuration_from(options_.config), participant_, log_);
  } else {
    log_->info("traffic control off: robots avoid each other only locally (the Forklift thesis's behaviour)");
  }
  if (options_.maps.empty()) options_.maps = {options_.site.name};
  log_->info("maps of site '{}': {}", options_.site.name, model::join(options_.maps));
  started_wall_ = SimClock::wall_now();
  restore_pallets();
  for (const auto& [fleet, robot] : options_.config.all_robots()) parked_at_[robot->id] = robot->home;
  restore_orders();
  publish_site_state();
  publish_server_info();
  log_->info("serving site '{}' on DDS domain {} at time scale {}, dispatch '{}', automatic orders {}",
             options_.site.name, options_.domain, options_.time_scale,
             options_.config.settings.get_string("server.dispatch_policy"), auto_orders_ ? "on" : "off");
}

FleetServer::~FleetServer() = default;

void FleetServer::restore_pallets() {
  for (const auto& area : options_.site.loading_areas) pallet_at_[area.id] = false;
  auto stored = store_.load_pallets();
  if (stored.empty()) {
    // A fresh database: the pallets of the site file, standing exactly on their areas.
    int next_id = 1;
    for (const auto& area : options_.site.loading_areas) {
      if (area.pallet_at_start) stored.push_back({next_id++, area.pose, area.id, ""});
    }
  } else {
    log_->info("restored {} pallets from {}", stored.size(), store_.path());
  }
  for (auto& pallet : stored) update_pallet(std::move(pallet));
}

void FleetServer::update_pallet(model::PalletTruth pallet) {
  if (auto old = pallets_.find(pallet.pallet_id); old != pallets_.end() && !old->second.area_id.empty()) {
    pallet_at_[old->second.area_id] = false;
  }
  if (!pallet.area_id.empty() && pallet.carried_by.empty()) pallet_at_[pallet.area_id] = true;
  store_.save_pallet(pallet);
  pallet_writer_.write(pallet);
  pallets_[pallet.pallet_id] = std::move(pallet);
}

const model::PalletTruth* FleetServer::pallet_carried_by(const std::string& robot_id) const {
  for (const auto& [id, pallet] : pallets_) {
    if (pallet.carried_by == robot_id) return &pallet;
  }
  return nullptr;
}

const model::PalletTruth* FleetServer::pallet_on(const std::string& area_id) const {
  for (const auto& [id, pallet] : pallets_) {
    if (pallet.area_id == area_id && pallet.carried_by.empty()) return &pallet;
  }
  return nullptr;
}

void FleetServer::restore_orders() {
  const auto stored = store_.load_all();
  book_ = orders::OrderBook(store_.next_id());
  long open = 0;
  for (Order order : stored) {
    fill_steps(order);
    if (order.kind == orders::OrderKind::kMove && order.status == OrderStatus::kDone) {
      parked_at_[order.robot_id] = order.drop_area;
    }
    book_.restore(order);
    if (orders::is_final(order.status)) {
      order_info_writer_.write(info_of(order));
      continue;
    }
    ++open;
    if (order.status != OrderStatus::kQueued) {
      // Assigned before the restart: offer it to its robot again. A robot still working on it
      // acknowledges and goes on; its latched OrderState tells us how far it got, also if it
      // finished while we were down.
      send_assignment(order);
    }
    order_info_writer_.write(info_of(order));
  }
  if (!stored.empty()) {
    log_->info("restored {} orders from {} ({} open); next order id {}", stored.size(), store_.path(), open,
               book_.next_id());
  }
}

void FleetServer::publish_server_info() {
  model::ServerInfo info;
  info.server_id = "fleet-server";
  info.site = options_.site.name;
  info.loading_areas = options_.site.area_ids();
  for (const auto& home : options_.site.homes) info.homes.push_back(home.id);
  for (const auto& [fleet, robot] : options_.config.all_robots()) info.robots.push_back(robot->id);
  for (const auto& o : options_.site.static_obstacles) info.obstacles.push_back(o.id);
  info.maps = options_.maps;
  info.time_scale = options_.time_scale;
  info.started_unix_ms = static_cast<std::int64_t>(SimClock::wall_now() * 1000.0);
  server_info_writer_.write(info);
}

void FleetServer::publish_site_state() {
  // [Forklift thesis, section 3]: the map is assigned at the start; obstacles are forwarded when they
  // change and when robots start (latched topics give late joiners the current set).
  for (const auto& [fleet, robot] : options_.config.all_robots()) control_writer_.write({robot->id, false});
  publish_map_and_obstacles();
}

void FleetServer::publish_map_and_obstacles() {
  for (const auto& [fleet, robot] : options_.config.all_robots()) map_writer_.write({robot->id, options_.site.name});
  for (const auto& obstacle : options_.site.static_obstacles) {
    obstacle_writer_.write({obstacle.id, options_.site.name, obstacle_enabled_[obstacle.id], obstacle.polygon});
  }
}

void FleetServer::reset_obstacles() {
  obstacle_enabled_.clear();
  for (const auto& obstacle : options_.site.static_obstacles)
    obstacle_enabled_[obstacle.id] = obstacle.enabled_at_start;
}

std::string FleetServer::switch_map(const std::string& map_id) {
  std::shared_ptr<const map::SiteMap> next;
  try {
    next = std::make_shared<const map::SiteMap>(
        map::load_site_map((std::filesystem::path(options_.site.file).parent_path() / (map_id + ".yaml")).string()));
  } catch (const std::exception& e) {
    return std::string("map '") + map_id + "' cannot be loaded: " + e.what();
  }
  if (std::string why = map::revision_mismatch(options_.site, next->site); !why.empty()) return why;
  // A robot standing on a road the new map closes would be off its graph with no way back onto
  // it: it waited there until the map was switched back. Refused, as an obstacle over a robot is.
  if (options_.site_map) {
    constexpr double kOnRoadM = 0.15;     // half a lane: the robot stands on that road
    constexpr double kSamePointM = 0.02;  // a point the new graph has too
    const auto& old_points = options_.site_map->graph.graph.points;
    const auto& new_points = next->graph.graph.points;
    for (const auto& [id, robot] : robots_) {
      if (!robot.registered) continue;
      const geometry::Vec2 at = robot.last.pose.position();
      for (const auto& p : old_points) {
        if (geometry::distance(at, {p.x, p.y}) > kOnRoadM) continue;
        const bool kept = std::any_of(new_points.begin(), new_points.end(), [&](const auto& q) {
          return geometry::distance({p.x, p.y}, {q.x, q.y}) <= kSamePointM;
        });
        if (!kept) {
          return fmt::format("robot {} stands at ({:.2f}, {:.2f}) on a road map '{}' closes: switch once it has left",
                             id, at.x, at.y, map_id);
        }
      }
    }
  }
  const std::string previous = options_.site.name;
  options_.site_map = next;
  options_.site = next->site;
  travel_ = planning::RoadPlanner(next->graph.graph);
  if (traffic_) {
    // Routes on the old graph mean nothing on the new one: every agent replans and enters anew.
    traffic_.reset();
    traffic_ = std::make_unique<TrafficControl>(next->graph.graph, traffic::configuration_from(options_.config),
                                                participant_, log_);
    // Where every robot stands, before any of them enters the new graph.
    for (const auto& [id, robot] : robots_) {
      if (robot.registered) traffic_->set_body(id, body_of(robot));  // lost ones too: still there
    }
  }
  reset_obstacles();
  publish_map_and_obstacles();
  publish_server_info();
  log_->info("map switched from '{}' to '{}' for every robot", previous, options_.site.name);
  return "";
}

void FleetServer::run(const std::atomic<bool>& stop) {
  ProcessMemory memory;
  while (!stop.load()) {
    waitset_.wait(std::chrono::milliseconds(5));
    handle_order_requests();
    handle_commands();
    handle_robot_states();
    handle_robot_paths();
    handle_order_reports();
    handle_web_requests();
    check_robot_health();
    if (traffic_) {
      // Traffic cycles at 20 Hz of sim time, at most 100 Hz of wall time at high time scales.
      const double now_sim = clock_.now();
      const double now_wall = SimClock::wall_now();
      traffic_->handle_requests(now_sim, now_wall);
      if (now_sim >= next_traffic_sim_ && now_wall - last_traffic_wall_ >= 0.01) {
        traffic_->update(now_sim, now_wall);
        next_traffic_sim_ = now_sim + 0.05;
        last_traffic_wall_ = now_wall;
      }
    }
    check_acknowledgements();
    if (auto_orders_) create_auto_orders();
    dispatch();
    publish_fleet_view();
    publish_web_snapshot();
    memory.tick(SimClock::wall_now());
  }
  log_->info("stopping; {} orders known", book_.all().size());
}

void FleetServer::reply(const model::RequestReply& answer) {
  reply_writer_.write(answer);
  replies_written_[answer.request_id] = SimClock::wall_now();
}

bool FleetServer::registered(const std::string& robot_id) const {
  const auto it = robots_.find(robot_id);
  return it != robots_.end() && it->second.registered;
}

std::optional<std::string> FleetServer::not_seen(const std::string& robot_id) const {
  if (registered(robot_id)) return std::nullopt;
  std::vector<std::string> seen;
  for (const auto& [id, robot] : robots_) {
    if (robot.registered) seen.push_back(id);
  }
  return "robot " + robot_id + " is configured but has not been seen: no fleet-agent --id " + robot_id +
         " has reported to this server" + (seen.empty() ? std::string() : " (seen: " + model::join(seen) + ")");
}

orders::KnownNames FleetServer::known_names() const {
  return orders::known_names(options_.config, options_.site);
}

void FleetServer::fill_steps(Order& order) const {
  const auto names = known_names();
  order.steps = orders::steps_of({std::string(orders::to_string(order.kind)), order.pick_area, order.drop_area, "",
                                  "", order.priority},
                                 names);
}

std::string FleetServer::validate_parking(const std::string& place, const std::string& robot_id) const {
  for (const auto& [robot, parked] : parked_at_) {
    if (parked == place && robot != robot_id) return "parking place '" + place + "' is " + robot + "'s";
  }
  for (const auto& [id, o] : book_.all()) {
    if (!orders::is_final(o.status) && o.kind == orders::OrderKind::kMove && o.drop_area == place) {
      return "parking place '" + place + "' is promised to order " + std::to_string(id) + ", which goes there";
    }
  }
  return "";
}

int FleetServer::expected_pallets(const std::string& area) const {
  // What will stand at `area` once every open order is done: a pallet there now, minus open
  // orders taking it away, plus open orders bringing one.
  int balance = pallet_at_.at(area) ? 1 : 0;
  for (const auto& [id, o] : book_.all()) {
    if (orders::is_final(o.status)) continue;
    if (o.pick_area == area) --balance;
    if (o.drop_area == area) ++balance;
  }
  return balance;
}

std::string FleetServer::validate_areas(const std::string& pick, const std::string& drop) const {
  // The names were checked (check_order_request); what is left is the pallets, counted once every
  // open order is done. A refusal says what is true now: a pallet there, or an order's promise.
  auto open_order = [&](auto&& uses_area) -> const Order* {
    for (const auto& [id, o] : book_.all()) {
      if (!orders::is_final(o.status) && uses_area(o)) return &o;
    }
    return nullptr;
  };
  if (expected_pallets(pick) <= 0) {
    if (const Order* taker = open_order([&](const Order& o) { return o.pick_area == pick; })) {
      return "the pallet on loading area '" + pick + "' is promised to order " + std::to_string(taker->id) +
             ", which picks it up";
    }
    return "loading area '" + pick + "' holds no pallet to pick";
  }
  if (expected_pallets(drop) > 0) {
    if (const Order* bringer = open_order([&](const Order& o) { return o.drop_area == drop; })) {
      return "loading area '" + drop + "' is promised to order " + std::to_string(bringer->id) +
             ", which drops its pallet there";
    }
    return "loading area '" + drop + "' holds a pallet";
  }
  return "";
}

void FleetServer::handle_order_requests() {
  request_reader_.take_data([&](model::OrderRequest&& request) {
    const model::RequestReply answer = execute(request);
    reply(answer);
  });
}

model::RequestReply FleetServer::execute(const model::OrderRequest& request) {
  auto refuse = [&](const std::string& error) {
    log_->warn("order request {} refused: {}", request.request_id, error);
    return model::RequestReply{request.request_id, false, 0, error};
  };
  const orders::OrderRequestFields fields{request.kind,     request.pick_area, request.drop_area,
                                          request.robot_id, request.fleet_id,  request.priority};
  if (const auto problem = orders::check_order_request(fields, known_names())) {
    return refuse(problem->field + ": " + problem->message);
  }
  const orders::OrderKind kind = orders::kind_of(fields);
  if (!request.robot_id.empty()) {
    // An order for a robot that never reported would wait for it for good, unseen.
    if (const auto why = not_seen(request.robot_id)) return refuse(*why);
  }
  const std::string error = kind == orders::OrderKind::kMove ? validate_parking(request.drop_area, request.robot_id)
                                                              : validate_areas(request.pick_area, request.drop_area);
  if (!error.empty()) return refuse(error);
  if (options_.config.settings.get_bool("server.reject_when_busy")) {
    const bool any_free =
        std::any_of(robots_.begin(), robots_.end(), [&](const auto& entry) { return robot_is_free(entry.second); });
    if (!any_free) return refuse("no robot is free (server.reject_when_busy is on)");
  }
  Order draft;
  draft.kind = kind;
  draft.request_id = request.request_id;
  draft.pick_area = request.pick_area;
  draft.drop_area = request.drop_area;
  draft.fleet_id = request.fleet_id;
  draft.robot_id = request.robot_id;
  draft.robot_requested = !request.robot_id.empty();
  draft.priority = request.priority;
  fill_steps(draft);
  const Order& order = book_.create(std::move(draft), clock_.now());
  log_->info("order {} created: {} {} -> {} (request {})", order.id, orders::to_string(order.kind), order.pick_area,
             order.drop_area, order.request_id);
  publish_order(order);  // stored before the requester hears of it
  return {request.request_id, true, order.id, ""};
}

void FleetServer::handle_commands() {
  command_reader_.take_data([&](model::Command&& command) { reply(execute(command)); });
}

model::RequestReply FleetServer::execute(const model::Command& command) {
  std::string error;
  if (command.verb == "cancel-order") {
    std::int64_t id = 0;
    try {
      id = std::stoll(command.target);
    } catch (const std::exception&) {
      error = "order id '" + command.target + "' is not a number";
    }
    const Order* order = error.empty() ? book_.find(id) : nullptr;
    if (error.empty() && !order) error = "unknown order " + command.target;
    if (order) {
      const bool was_assigned = !order->robot_id.empty() && order->status != OrderStatus::kQueued;
      if (book_.transition(id, OrderStatus::kCancelled, clock_.now(), "cancelled by operator") !=
          TransitionResult::kApplied) {
        error = "order " + command.target + " is already " + std::string(orders::to_string(order->status));
      } else {
        log_->info("order {} cancelled by operator", id);
        publish_order(*order);
        if (was_assigned) withdraw(*order, order->robot_id);
      }
    }
  } else if (command.verb == "obstacle") {
    if (!options_.site.find_obstacle(command.target)) {
      std::vector<std::string> ids;
      for (const auto& o : options_.site.static_obstacles) ids.push_back(o.id);
      error = model::unknown_name_message("obstacle", command.target, ids);
    } else if (command.value != "on" && command.value != "off") {
      error = "obstacle state '" + command.value + "' is not on or off";
    } else if (const std::string robot_id =
                   command.value == "on" ? robot_under(*options_.site.find_obstacle(command.target)) : "";
               !robot_id.empty()) {
      // A robot cannot leave an obstacle switched on over it (every way out starts inside it),
      // and a real one cannot be where a real obstacle is.
      const auto& pose = robots_.at(robot_id).last.pose;
      error = fmt::format("obstacle {} covers robot {} at ({:.2f}, {:.2f}): switch it on once the robot has left",
                          command.target, robot_id, pose.x, pose.y);
    } else {
      obstacle_enabled_[command.target] = command.value == "on";
      const auto* obstacle = options_.site.find_obstacle(command.target);
      obstacle_writer_.write({obstacle->id, options_.site.name, command.value == "on", obstacle->polygon});
      log_->info("static obstacle {} {}", command.target, command.value);
    }
  } else if (command.verb == "map") {
    // [Forklift thesis, section 3]: maps are assigned at the start and whenever the user changes them.
    std::vector<std::string> robot_ids;
    for (const auto& [fleet, robot] : options_.config.all_robots()) robot_ids.push_back(robot->id);
    const bool one_robot = !command.target.empty() && command.target != "all";
    if (std::find(options_.maps.begin(), options_.maps.end(), command.value) == options_.maps.end()) {
      error = model::unknown_name_message("map", command.value, options_.maps);
    } else if (one_robot && std::find(robot_ids.begin(), robot_ids.end(), command.target) == robot_ids.end()) {
      error = model::unknown_name_message("robot", command.target, robot_ids);
    } else if (one_robot && traffic_) {
      error =
          "traffic control needs every robot on the same map: switch them all (no robot given), or run "
          "with traffic.enabled false";
    } else if (one_robot) {
      map_writer_.write({command.target, command.value});
      log_->info("robot {} switched to map '{}'", command.target, command.value);
    } else if (command.value != options_.site.name) {
      error = switch_map(command.value);
    }
  } else if (command.verb == "auto-orders") {
    if (command.value != "on" && command.value != "off") {
      error = "auto-orders value '" + command.value + "' is not on or off";
    } else {
      auto_orders_ = command.value == "on";
      log_->info("automatic orders {}", command.value);
    }
  } else if (command.verb == "pause" || command.verb == "resume") {
    if (!options_.config.find_robot(command.target)) {
      error = model::unknown_name_message("robot", command.target, known_names().robots);
    } else if (const auto why = not_seen(command.target)) {
      error = *why;
    } else {
      paused_[command.target] = command.verb == "pause";
      control_writer_.write({command.target, command.verb == "pause"});
      log_->info("robot {} {}d by operator", command.target, command.verb);
    }
  } else {
    error = "unknown command '" + command.verb + "' (cancel-order, obstacle, map, auto-orders, pause, resume)";
  }
  if (!error.empty()) log_->warn("command {} {} {} refused: {}", command.verb, command.target, command.value, error);
  return {command.request_id, error.empty(), 0, error};
}

void FleetServer::handle_robot_states() {
  robot_state_reader_.take([&](model::RobotState&& state, const dds::SampleInfo& info) {
    if (!info.valid_data) {
      // DDS liveliness: the robot's writer is gone (its participant's 1 s lease expired or it
      // left). Only the key is valid in such a sample.
      auto it = robots_.find(state.robot_id);
      if (!info.alive && it != robots_.end() && it->second.registered && !it->second.lost) {
        robot_lost(it->second, "DDS liveliness lost");
      }
      return;
    }
    if (!std::isfinite(state.pose.x) || !std::isfinite(state.pose.y) || !std::isfinite(state.pose.yaw)) {
      log_->warn("robot {}: ignoring RobotState with a non-finite pose ({}, {}, {})", state.robot_id, state.pose.x,
                 state.pose.y, state.pose.yaw);
      return;
    }
    const auto known = options_.config.find_robot(state.robot_id);
    if (!known) {
      log_->warn("ignoring RobotState of robot '{}', which is not in {}", state.robot_id, options_.config.source);
      return;
    }
    RobotEntry& robot = robots_[state.robot_id];
    if (!robot.registered || robot.lost) {
      log_->info("robot {} ({}) {} at ({:.2f}, {:.2f}), state {}", state.robot_id, known->first->id,
                 robot.lost ? "is back" : "registered", state.pose.x, state.pose.y, state.task_state);
      // A robot that comes back may still report an order the server has moved on from:
      // tell it so (the latched Order carries the cancellation).
      if (state.order_id != 0) {
        const Order* order = book_.find(state.order_id);
        if (order && (order->robot_id != state.robot_id || orders::is_final(order->status))) {
          withdraw(*order, state.robot_id);
        }
      }
    }
    if (robot.lost) resume_or_fail_waiting_orders(state);
    robot.id = state.robot_id;
    robot.fleet_id = known->first->id;
    robot.registered = true;
    robot.lost = false;
    if (robot.stalled) log_->info("robot {} publishes again after a missed deadline", state.robot_id);
    robot.stalled = false;
    robot.last_seen_wall = SimClock::wall_now();
    robot.last = std::move(state);
    if (traffic_) traffic_->set_body(robot.id, body_of(robot));
  });
}

void FleetServer::handle_robot_paths() {
  robot_path_reader_.take_data([&](model::RobotPath&& path) { paths_[path.robot_id] = std::move(path); });
  truth_reader_.take_data([&](model::SimTruth&& truth) { truths_[truth.robot_id] = std::move(truth); });
}

void FleetServer::handle_web_requests() {
  if (!bridge_) return;
  for (auto& pending : bridge_->drain()) {
    pending.reply.set_value(std::visit([&](const auto& request) { return execute(request); }, pending.request));
  }
}

void FleetServer::publish_web_snapshot() {
  constexpr double kWebHzWall = 20.0;
  constexpr std::size_t kRecentEndedOrders = 50;
  if (!bridge_) return;
  const double now_wall = SimClock::wall_now();
  if (now_wall - last_web_snapshot_wall_ < 1.0 / kWebHzWall) return;
  last_web_snapshot_wall_ = now_wall;
  LiveSnapshot snap;
  snap.map = options_.site.name;
  snap.site_map = options_.site_map;
  snap.sim_time = clock_.now();
  snap.time_scale = options_.time_scale;
  const double lost_after = options_.config.settings.get_double("server.robot_lost_after_s");
  for (const auto& [id, robot] : robots_) {
    if (!robot.registered) continue;
    RobotView view;
    view.state = robot.last;
    if (auto t = truths_.find(id); t != truths_.end()) view.truth = t->second;
    if (auto p = paths_.find(id); p != paths_.end()) view.path = p->second.points;
    if (const auto spec = options_.config.find_robot(id)) view.footprint = spec->first->footprint;
    const double silent_wall = now_wall - robot.last_seen_wall;
    view.health = robot.lost ? "lost" : (robot.stalled || silent_wall > lost_after / 2 ? "stale" : "alive");
    view.age_s = std::max(0.0, snap.sim_time - robot.last.sim_time);
    if (traffic_) {
      if (auto t = traffic_->status().find(id); t != traffic_->status().end()) {
        view.traffic = t->second.status;
        view.waiting_for = t->second.blocked_by;
        view.reserved = t->second.held;
      }
    }
    snap.robots.push_back(std::move(view));
  }
  std::vector<const Order*> ended;
  std::vector<double> durations;
  for (const auto& [id, order] : book_.all()) {
    if (!orders::is_final(order.status)) {
      snap.orders.push_back(info_of(order));
    } else {
      ended.push_back(&order);
    }
    if (order.status == OrderStatus::kDone) {
      ++snap.orders_done;
      durations.push_back(order.finished_sim - order.created_sim);
    }
    if (order.status == OrderStatus::kFailed) ++snap.orders_failed;
  }
  for (std::size_t i = ended.size() > kRecentEndedOrders ? ended.size() - kRecentEndedOrders : 0; i < ended.size();
       ++i) {
    snap.orders.push_back(info_of(*ended[i]));
  }
  // The same p95 as `fleetctl stats`, so the page and the CLI agree.
  snap.order_time_p95_s = monitor::percentile(std::move(durations), 0.95);
  const double hours = (snap.sim_time - started_wall_ * options_.time_scale) / 3600.0;
  snap.orders_per_hour = hours > 0 ? snap.orders_done / hours : 0.0;
  snap.obstacle_enabled = obstacle_enabled_;
  snap.pallet_at = pallet_at_;
  snap.auto_orders = auto_orders_;
  bridge_->publish(std::move(snap));
}

void FleetServer::handle_order_reports() {
  order_report_reader_.take_data([&](model::OrderReport&& report) {
    const Order* order = book_.find(report.order_id);
    if (!order) {
      log_->warn("report on unknown order {} from {}", report.order_id, report.robot_id);
      return;
    }
    if (order->robot_id != report.robot_id || report.update_id != order->update_id) {
      if (hand_back(*order, report)) return;
      // A late duplicate or a report from a robot the order was taken from (VDA 5050 style).
      log_->debug("ignoring stale report {} on order {} from {} (update {} vs {})", report.status, report.order_id,
                  report.robot_id, report.update_id, order->update_id);
      return;
    }
    if ((report.status == "DONE" && order->status == OrderStatus::kDone) ||
        (report.status == "FAILED" && order->status == OrderStatus::kFailed)) {
      // Reports are kept for late joiners: a restarted server hears every robot's finished
      // orders again. The same end state twice is news to no one.
      log_->debug("order {}: {} repeated by {}", order->id, report.status, report.robot_id);
      return;
    }
    if (orders::is_final(order->status)) {
      // The robot runs an order that has ended: it read the latched assignment as it restarted,
      // just before the order was failed for its return with empty forks. Left alone, it would
      // carry a pallet for an order no one counts.
      log_->warn("order {} is {}, but {} reports {}: told it to drop the order", order->id,
                 orders::to_string(order->status), report.robot_id, report.status);
      withdraw(*order, report.robot_id);
      return;
    }
    const double now = clock_.now();
    const std::int64_t id = order->id;
    awaiting_ack_since_.erase(id);
    TransitionResult result = TransitionResult::kApplied;
    if (report.status == "ACCEPTED") {
      log_->info("order {} accepted by {}", id, report.robot_id);
      return;
    } else if (report.status == "REJECTED") {
      log_->warn("order {} rejected by {}: {}", id, report.robot_id, report.reason);
      result = book_.requeue(id, now, "rejected by " + report.robot_id + ": " + report.reason);
      // Its published state may lag its real one: do not offer it another order at once.
      rejected_at_wall_[report.robot_id] = SimClock::wall_now();
    } else if (report.status == "DONE" && order->kind == orders::OrderKind::kMove) {
      result = book_.transition(id, OrderStatus::kDone, now);
      if (result == TransitionResult::kApplied) {
        parked_at_[report.robot_id] = order->drop_area;
        log_->info("order {} done: {} parks at {}", id, report.robot_id, order->drop_area);
      }
    } else if (report.status == "DONE") {
      result = book_.transition(id, OrderStatus::kDone, now);
      if (result == TransitionResult::kApplied) {
        // The pallet stands where the robot really put it (simulation truth), so a sloppy drop
        // makes the next pick from that area harder.
        const auto* drop = options_.site.find_area(order->drop_area);
        auto carried = pallets_.find(report.pallet_id);
        if (carried == pallets_.end()) {
          log_->warn("order {} done by {} without naming the pallet it put down; pallet truth unchanged", id,
                     report.robot_id);
          pallet_at_[order->drop_area] = true;
        } else {
          model::PalletTruth pallet = carried->second;
          pallet.pose = report.pallet_pose;
          pallet.carried_by.clear();
          pallet.area_id = order->drop_area;
          const double error = drop ? geometry::distance(pallet.pose.position(), drop->pose.position()) : 0.0;
          update_pallet(std::move(pallet));
          log_->info("order {} done by {}: pallet {} placed at {} ({:.3f} m from the area's centre)", id,
                     report.robot_id, report.pallet_id, order->drop_area, error);
        }
      }
    } else if (report.status == "FAILED") {
      result = book_.transition(id, OrderStatus::kFailed, now, report.reason);
      if (result == TransitionResult::kApplied) {
        log_->warn("order {} failed on {}: {}", id, report.robot_id, report.reason);
        if (report.reason.find("empty") != std::string::npos) {
          // A search that finds no pallet where one was put down is a miss of the robot's camera
          // or estimate, not news that the area is free: taking it for free would let a later
          // order put a second pallet on the first. Only an area without a recorded pallet is
          // marked free.
          if (const auto* standing = pallet_on(order->pick_area)) {
            log_->warn(
                "order {}: {} found loading area {} empty, but pallet {} stands there at ({:.3f}, {:.3f}) "
                "by the record; the area stays occupied",
                id, report.robot_id, order->pick_area, standing->pallet_id, standing->pose.x, standing->pose.y);
          } else {
            pallet_at_[order->pick_area] = false;
          }
        }
      }
    } else if (const auto phase = orders::parse_phase(report.status)) {
      if (*phase == order->phase) return;
      result = book_.set_phase(id, *phase, now);
      if (result == TransitionResult::kApplied) {
        log_->info("order {} on {}: {}", id, report.robot_id, report.status);
        // [Forklift thesis, section 8]: the server keeps the pallet map up to date as robots pick.
        if (report.carrying_pallet && past_the_lift(*phase)) {
          auto lifted = pallets_.find(report.pallet_id);
          if (lifted == pallets_.end()) {
            if (const auto* standing = pallet_on(order->pick_area)) lifted = pallets_.find(standing->pallet_id);
          }
          if (lifted != pallets_.end() && lifted->second.carried_by != report.robot_id) {
            model::PalletTruth pallet = lifted->second;
            pallet.carried_by = report.robot_id;
            pallet.area_id.clear();
            update_pallet(std::move(pallet));
            log_->info("pallet {} lifted by {} from {}", lifted->first, report.robot_id, order->pick_area);
          }
        }
      }
    } else {
      log_->warn("order {}: unknown status '{}' from {}", id, report.status, report.robot_id);
      return;
    }
    if (result == TransitionResult::kIllegal) {
      log_->warn("order {}: refused illegal transition {} -> {} reported by {}", id,
                 orders::to_string(book_.find(id)->status), report.status, report.robot_id);
      return;
    }
    publish_order(*book_.find(id));
  });
}

std::string FleetServer::robot_under(const map::StaticObstacle& obstacle) const {
  for (const auto& [id, robot] : robots_) {
    if (robot.registered && geometry::polygons_overlap(obstacle.polygon, body_of(robot))) return id;
  }
  return "";
}

geometry::Polygon FleetServer::body_of(const RobotEntry& robot) const {
  geometry::Footprint footprint;
  if (const auto spec = options_.config.find_robot(robot.id)) footprint = spec->first->footprint;
  return geometry::footprint_polygon(robot.last.pose, footprint);
}

void FleetServer::robot_lost(RobotEntry& robot, const std::string& why) {
  robot.lost = true;
  log_->warn("robot {} lost: {}", robot.id, why);
  // Where its body was last seen stays blocked: a dead robot is still in the way.
  if (traffic_) traffic_->robot_lost(robot.id, body_of(robot), clock_.now());
  if (const Order* order = book_.open_order_of(robot.id)) {
    const std::int64_t id = order->id;
    // Lost at the pick area, searching or picking, it may be lifting the pallet as it froze, or
    // do so within a second of answering again, before a withdrawal reaches it: like one lost with
    // the pallet on its forks, only this robot can finish the order, and a stalled robot carries
    // on when it answers again. (Re-queued instead, the order was withdrawn from it as it came
    // back with the pallet, and it stood in the lane with it for good.)
    if (robot.last.carrying_pallet || at_pick_area(order->phase)) {
      awaiting_lost_robot_.emplace(id, SimClock::wall_now());
      log_->warn("order {} waits for robot {}: lost {} (at most {:.0f} s)", id, robot.id,
                 robot.last.carrying_pallet ? "with the pallet on its forks" : "at the pick area",
                 options_.config.settings.get_double("server.lost_with_pallet_wait_s"));
      return;
    }
    requeue_taken_from(id, robot.id, "robot " + robot.id + " lost");
  }
}

void FleetServer::requeue_taken_from(std::int64_t order_id, const std::string& robot_id, const std::string& reason) {
  if (book_.requeue(order_id, clock_.now(), reason) != TransitionResult::kApplied) return;
  log_->warn("order {} re-queued: {}", order_id, reason);
  awaiting_ack_since_.erase(order_id);
  publish_order(*book_.find(order_id));
  withdraw(*book_.find(order_id), robot_id);
}

bool FleetServer::hand_back(const Order& order, const model::OrderReport& report) {
  // A robot lost on its way to the pick had its order re-queued; answering again, it may reach
  // the pick area, search and lift the pallet before the withdrawal reaches it. It cannot put the
  // pallet back (no cancel after the pick [Forklift thesis, section 6.4]) and carries the order on; no other
  // robot can pick that pallet now. So the order goes back to it, unless its new robot has
  // lifted a pallet for it already.
  const auto phase = orders::parse_phase(report.status);
  const bool lifted = report.carrying_pallet && phase && past_the_lift(*phase);
  if (!lifted || report.robot_id == order.robot_id || orders::is_final(order.status)) return false;
  if (order.phase == OrderPhase::kPicking || past_the_lift(order.phase)) return false;
  // Counted lost still, it is back all the same: its report may come before its first state
  // (and is not sent again), and was written after it fell silent.
  if (!registered(report.robot_id)) return false;
  const std::int64_t id = order.id;
  const std::string holder = order.robot_id;
  const double now = clock_.now();
  if (order.status != OrderStatus::kQueued) {
    if (book_.requeue(id, now, "handed back to " + report.robot_id + ", which has the pallet") !=
        TransitionResult::kApplied) {
      return false;
    }
    withdraw(*book_.find(id), holder);
  }
  if (book_.assign(id, report.robot_id, now) != TransitionResult::kApplied) return false;
  const Order& handed = *book_.find(id);
  log_->warn("order {} handed back to {}: it lifted the pallet at {} before the order's withdrawal reached it{}", id,
             report.robot_id, handed.pick_area, holder.empty() ? "" : " (taken from " + holder + ")");
  awaiting_lost_robot_.erase(id);
  resends_[id] = 0;
  publish_order(handed);
  send_assignment(handed);
  return true;
}

void FleetServer::fail_with_pallet(std::int64_t order_id, const std::string& reason) {
  if (book_.transition(order_id, OrderStatus::kFailed, clock_.now(), reason) != TransitionResult::kApplied) return;
  log_->warn("order {} failed: {}", order_id, reason);
  awaiting_ack_since_.erase(order_id);
  publish_order(*book_.find(order_id));
}

void FleetServer::return_pallet_of(const std::string& robot_id, const std::string& preferred_area) {
  // A simulated robot restarts at its home with empty forks, so the pallet it carried would be
  // nowhere, and a fleet that loses one pallet per crash soon has no work. Where a real fleet's
  // operator takes the pallet off the crashed robot and puts it back, the simulation puts it on
  // the order's pick area, or the first free one.
  const model::PalletTruth* carried = pallet_carried_by(robot_id);
  if (!carried) return;
  const map::LoadingArea* area = options_.site.find_area(preferred_area);
  if (!area || pallet_on(area->id)) {
    area = nullptr;
    for (const auto& a : options_.site.loading_areas) {
      if (!pallet_on(a.id)) {
        area = &a;
        break;
      }
    }
  }
  if (!area) {
    log_->warn("pallet {} of restarted robot {} has no free loading area to go back to", carried->pallet_id, robot_id);
    return;
  }
  model::PalletTruth pallet = *carried;
  pallet.pose = area->pose;
  pallet.area_id = area->id;
  pallet.carried_by.clear();
  log_->info("pallet {} of restarted robot {} put back on {} (simulation: the operator's part)", pallet.pallet_id,
             robot_id, area->id);
  update_pallet(std::move(pallet));
}

void FleetServer::give_up_on_lost_robot(std::int64_t order_id, const std::string& why, const std::string& failure) {
  const Order* order = book_.find(order_id);
  if (!order) return;
  const std::string robot_id = order->robot_id;
  if (!pallet_carried_by(robot_id)) {
    // Lost at the pick area before the lift: the pallet still stands there.
    requeue_taken_from(order_id, robot_id, why + " before lifting the pallet");
    return;
  }
  const std::string pick_area = order->pick_area;
  fail_with_pallet(order_id, failure);
  return_pallet_of(robot_id, pick_area);
}

void FleetServer::resume_or_fail_waiting_orders(const model::RobotState& state) {
  for (auto it = awaiting_lost_robot_.begin(); it != awaiting_lost_robot_.end();) {
    const Order* order = book_.find(it->first);
    if (!order || order->robot_id != state.robot_id) {
      ++it;
      continue;
    }
    const std::int64_t id = it->first;
    it = awaiting_lost_robot_.erase(it);
    if (orders::is_final(order->status)) continue;
    // A restarted agent may report the order too: it read the latched assignment before its
    // first state, and runs the order from the start. Its forks are empty while the pallet truth
    // has the pallet on them (and it was not putting it down). The order's phase does not tell:
    // the restarted agent's TO_PICK report can arrive before its first state.
    const bool dropping = order->phase == OrderPhase::kDropping;
    const bool restarted =
        state.order_id != id || (pallet_carried_by(state.robot_id) && !state.carrying_pallet && !dropping);
    if (!restarted) {
      // Its software still runs the order: the pallet is on its forks, or it was put down at the
      // drop area as the robot froze and the DONE report follows, or it was still at the pick.
      log_->info("order {} resumes: robot {} is back with it ({})", id, state.robot_id,
                 state.carrying_pallet        ? "pallet on its forks"
                 : at_pick_area(order->phase) ? "still at the pick area"
                                              : "pallet put down at the drop area");
    } else {
      give_up_on_lost_robot(id, "robot " + state.robot_id + " came back restarted",
                            "robot " + state.robot_id + " came back without the order's pallet (restarted)");
      if (state.order_id == id) withdraw(*book_.find(id), state.robot_id);
    }
  }
}

void FleetServer::check_robot_health() {
  const double now = SimClock::wall_now();
  const double lost_after = options_.config.settings.get_double("server.robot_lost_after_s");
  // DDS deadline on RobotState (0.5 s, dds::qos::robot_state): the robot is stalled — frozen,
  // or its link is — before its lease runs out and it is lost.
  while (const auto missed = robot_state_reader_.deadline_missed()) {
    auto it = robots_.find(missed->robot_id);
    if (it != robots_.end() && it->second.registered && !it->second.lost && !it->second.stalled) {
      it->second.stalled = true;
      log_->warn("robot {} stalled: no RobotState within its 0.5 s DDS deadline", it->first);
    }
  }
  for (auto& [id, robot] : robots_) {
    if (robot.registered && !robot.lost && now - robot.last_seen_wall > lost_after) {
      robot_lost(robot, "no RobotState for " + std::to_string(now - robot.last_seen_wall).substr(0, 4) + " s");
    }
  }
  const double pallet_wait = options_.config.settings.get_double("server.lost_with_pallet_wait_s");
  for (auto it = awaiting_lost_robot_.begin(); it != awaiting_lost_robot_.end();) {
    const Order* order = book_.find(it->first);
    if (!order || orders::is_final(order->status)) {
      it = awaiting_lost_robot_.erase(it);
    } else if (now - it->second > pallet_wait) {
      const std::int64_t id = it->first;
      const std::string robot_id = order->robot_id;
      it = awaiting_lost_robot_.erase(it);
      const std::string waited = std::to_string(static_cast<int>(pallet_wait)) + " s";
      give_up_on_lost_robot(id, "robot " + robot_id + " lost for " + waited,
                            "robot " + robot_id + " lost with the pallet for " + waited);
    } else {
      ++it;
    }
  }
  // Orders restored from the database whose robot has not shown up since the restart: after a
  // grace period the robot counts as lost. A robot in TO_DROP or DROPPING had the pallet on board.
  if (now - started_wall_ > std::max(3.0, 3.0 * lost_after)) {
    for (const auto& [order_id, order] : book_.all()) {
      if (orders::is_final(order.status) || order.status == OrderStatus::kQueued) continue;
      if (robots_.contains(order.robot_id)) continue;
      RobotEntry& ghost = robots_[order.robot_id];
      ghost.id = order.robot_id;
      ghost.registered = false;
      ghost.last.carrying_pallet = order.phase == OrderPhase::kToDrop || order.phase == OrderPhase::kDropping;
      robot_lost(ghost, "not seen since the server restarted");
      break;  // book_ changed; the next pass handles the rest
    }
  }
  // Replies are latched only long enough for their requester to read them; unregistering keeps
  // the writer's history bounded.
  for (auto it = replies_written_.begin(); it != replies_written_.end();) {
    if (now - it->second > kReplyRetentionWallS) {
      reply_writer_.unregister({it->first, false, 0, ""});
      it = replies_written_.erase(it);
    } else {
      ++it;
    }
  }
}

void FleetServer::check_acknowledgements() {
  const double now = SimClock::wall_now();
  const double timeout = options_.config.settings.get_double("server.order_ack_timeout_s");
  const long limit = options_.config.settings.get_int("server.order_resend_limit");
  for (auto it = awaiting_ack_since_.begin(); it != awaiting_ack_since_.end();) {
    const std::int64_t id = it->first;
    if (now - it->second < timeout) {
      ++it;
      continue;
    }
    const Order* order = book_.find(id);
    if (!order || order->status != OrderStatus::kAssigned) {
      it = awaiting_ack_since_.erase(it);
      continue;
    }
    if (resends_[id] < limit) {
      ++resends_[id];
      log_->warn("order {} not acknowledged by {} within {} s; re-sending ({}/{})", id, order->robot_id, timeout,
                 resends_[id], limit);
      send_assignment(*order);
      it->second = now;
      ++it;
    } else {
      const std::string robot = order->robot_id;
      book_.requeue(id, clock_.now(), "not acknowledged by " + robot);
      log_->warn("order {} re-queued: never acknowledged by {}", id, robot);
      publish_order(*book_.find(id));
      withdraw(*book_.find(id), robot);
      resends_.erase(id);
      it = awaiting_ack_since_.erase(it);
    }
  }
}

bool FleetServer::robot_is_free(const RobotEntry& robot) const {
  constexpr double kRejectionBackoffWall = 2.0;
  if (!robot.registered || robot.lost) return false;
  if (auto r = rejected_at_wall_.find(robot.id);
      r != rejected_at_wall_.end() && SimClock::wall_now() - r->second < kRejectionBackoffWall) {
    return false;
  }
  if (robot.last.task_state != "IDLE" && robot.last.task_state != "GO_HOME") return false;
  if (robot.last.carrying_pallet) return false;
  return book_.open_order_of(robot.id) == nullptr;
}

void FleetServer::create_auto_orders() {
  // [Forklift thesis, section 3]: random orders whenever a forklift is free, from an area holding a
  // pallet to a free one.
  const long free_robots =
      std::count_if(robots_.begin(), robots_.end(), [&](const auto& e) { return robot_is_free(e.second); });
  const long queued = static_cast<long>(book_.with_status(OrderStatus::kQueued).size());
  if (free_robots <= queued) return;
  // From a pallet standing there now to an area free now, neither promised to an open order:
  // an automatic order never waits on another.
  std::set<std::string> promised;
  for (const auto& [id, o] : book_.all()) {
    if (orders::is_final(o.status)) continue;
    promised.insert(o.pick_area);
    promised.insert(o.drop_area);
  }
  std::vector<std::string> picks, drops;
  for (const auto& area : options_.site.loading_areas) {
    if (promised.contains(area.id)) continue;
    (pallet_at_.at(area.id) ? picks : drops).push_back(area.id);
  }
  if (picks.empty() || drops.empty()) return;
  for (int attempt = 0; attempt < 16; ++attempt) {
    const std::string& pick = picks[rng_() % picks.size()];
    const std::string& drop = drops[rng_() % drops.size()];
    if (!validate_areas(pick, drop).empty()) continue;
    Order draft;
    draft.request_id = "auto";
    draft.pick_area = pick;
    draft.drop_area = drop;
    const Order& order = book_.create(std::move(draft), clock_.now());
    log_->info("order {} created automatically: {} -> {}", order.id, order.pick_area, order.drop_area);
    publish_order(order);
    return;
  }
}

void FleetServer::dispatch() {
  // An order goes out only when its pallet stands at the pick area and the drop area is free:
  // one chained behind another (A->B, then B->C) waits in the queue for the first to finish.
  std::vector<const Order*> queue;
  for (const Order* o : book_.queue()) {
    if (o->kind != orders::OrderKind::kTransport || (pallet_at_.at(o->pick_area) && !pallet_at_.at(o->drop_area))) {
      queue.push_back(o);
    }
  }
  if (queue.empty()) return;
  std::vector<orders::FreeRobot> free;
  const auto names = known_names();
  for (const auto& [id, robot] : robots_) {
    if (!robot_is_free(robot)) continue;
    const auto ability = std::find_if(names.abilities.begin(), names.abilities.end(),
                                      [&](const orders::FleetAbility& a) { return a.fleet_id == robot.fleet_id; });
    if (ability != names.abilities.end()) free.push_back({robot.id, robot.fleet_id, *ability});
  }
  if (free.empty()) return;
  const auto cost = [&](const std::string& robot_id, const std::string& area_id) {
    return travel_cost(robot_id, area_id);
  };
  for (const auto& assignment : policy_->assign(queue, free, cost)) {
    if (book_.assign(assignment.order_id, assignment.robot_id, clock_.now()) != TransitionResult::kApplied) continue;
    const Order& order = *book_.find(assignment.order_id);
    log_->info("order {} assigned to {}", order.id, order.robot_id);
    resends_[order.id] = 0;
    publish_order(order);
    send_assignment(order);
  }
}

double FleetServer::travel_cost(const std::string& robot_id, const std::string& place_id) {
  constexpr double kApproach = 0.30;  // the forklift picks standing this far out from the pallet
  const auto* area = options_.site.find_area(place_id);
  const auto* home = options_.site.find_home(place_id);
  const auto robot = robots_.find(robot_id);
  if ((!area && !home) || robot == robots_.end()) return std::numeric_limits<double>::infinity();
  const geometry::Pose2 approach =
      area ? geometry::Pose2{area->pose.x + kApproach * std::cos(area->pose.yaw),
                             area->pose.y + kApproach * std::sin(area->pose.yaw), area->pose.yaw}
           : home->pose;
  const planning::RoadPlan plan = travel_.plan(robot->second.last.pose, approach);
  if (plan.status != planning::PlanStatus::kFound) return std::numeric_limits<double>::infinity();
  return geometry::distance(robot->second.last.pose.position(), plan.points.front()) + plan.length;
}

void FleetServer::withdraw(const Order& order, const std::string& robot_id) {
  model::OrderAssignment msg;
  msg.order_id = order.id;
  msg.robot_id = robot_id;
  msg.update_id = order.update_id;
  msg.cancelled = true;
  order_writer_.write(msg);
  // An ended order must not stay on the latched topic (see publish_order): the robot has the
  // withdrawal once it is written, a robot that comes back later is told again on its return.
  if (orders::is_final(order.status)) order_writer_.unregister(msg);
}

void FleetServer::send_assignment(const Order& order) {
  model::OrderAssignment msg;
  msg.order_id = order.id;
  msg.robot_id = order.robot_id;
  msg.pick_area = order.pick_area;
  msg.drop_area = order.drop_area;
  if (const auto* pick = options_.site.find_area(order.pick_area)) msg.pick_pose = pick->pose;
  if (const auto* drop = options_.site.find_area(order.drop_area)) msg.drop_pose = drop->pose;
  if (const auto* parking = options_.site.find_home(order.drop_area); parking && order.kind == orders::OrderKind::kMove) {
    msg.drop_pose = parking->pose;
  }
  msg.kind = std::string(orders::to_string(order.kind));
  msg.update_id = order.update_id;
  order_writer_.write(msg);
  awaiting_ack_since_[order.id] = SimClock::wall_now();
}

void FleetServer::publish_order(const Order& order) {
  if (auto robot = robots_.find(order.robot_id);
      robot != robots_.end() && !order.history.empty() && !order.history.back().robot_id.empty()) {
    book_.locate_last_event(order.id, robot->second.last.pose.x, robot->second.last.pose.y);
  }
  // Written before anyone is told: a crash after this line loses nothing that was announced.
  store_.save(order);
  order_info_writer_.write(info_of(order));
  if (orders::is_final(order.status)) {
    // A finished order leaves the latched Order topic, so an agent that restarts never receives
    // it again; OrderInfo keeps the record.
    model::OrderAssignment key;
    key.order_id = order.id;
    order_writer_.unregister(key);
  }
}

void FleetServer::publish_fleet_view() {
  const double now_wall = SimClock::wall_now();
  const double period_wall = std::max(
      1.0 / kMaxRoutingHzWall, clock_.to_wall(1.0 / options_.config.settings.get_double("server.fleet_view_hz")));
  if (now_wall - last_fleet_view_wall_ < period_wall) return;
  last_fleet_view_wall_ = now_wall;
  std::map<std::string, model::FleetView> views;
  for (const auto& [id, robot] : robots_) {
    if (!robot.registered) continue;
    const auto spec = options_.config.find_robot(id);
    model::RobotSnapshot snap;
    snap.robot_id = id;
    snap.fleet_id = robot.fleet_id;
    snap.pose = robot.last.pose;
    if (spec) snap.footprint = spec->first->footprint;
    snap.speed = robot.last.speed;
    snap.task_state = robot.lost ? "LOST" : robot.last.task_state;
    snap.sim_time = robot.last.sim_time;
    if (auto p = paths_.find(id); p != paths_.end()) snap.path = p->second.points;
    const std::string map_id = robot.last.map_id.empty() ? options_.site.name : robot.last.map_id;
    auto& view = views[map_id];
    view.map_id = map_id;
    view.sim_time = clock_.now();
    view.robots.push_back(std::move(snap));
  }
  for (const auto& [map_id, view] : views) fleet_view_writer_.write(view);
}

}  // namespace fleet::server
