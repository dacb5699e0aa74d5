// Order requests and operator commands, dispatch and automatic orders, and what the robots are told.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "model/names.hpp"
#include "orders/packing_chain.hpp"
#include "orders/pick_lines.hpp"
#include "orders/transport_areas.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderStatus;
using orders::TransitionResult;

void FleetServer::handle_order_requests() {
  request_reader_.take_data([&](model::OrderRequest&& request) {
    const model::RequestReply answer = execute(request);
    reply(answer);
  });
}

model::RequestReply FleetServer::execute(const model::OrderRequest& request) {
  orders::IntakeDecision decision = orders::OrderIntake(intake_view()).decide(request);
  if (!decision.reply.accepted) {
    log_->warn("order request {} refused: {}", request.request_id, decision.reply.error);
    return decision.reply;
  }
  decision.reply.order_id = add_orders(std::move(decision.drafts));
  return decision.reply;
}

orders::IntakeView FleetServer::intake_view() const {
  orders::IntakeView view{.book = book_,
                          .ledger = ledger_,
                          .names = known_names(),
                          .site = options_.site,
                          .parked_at = parked_at_,
                          .registered = registered_robots(),
                          .free_robots = {},
                          .reject_when_busy = options_.config.settings.get_bool("server.reject_when_busy"),
                          .max_pickable_mass = orders::max_pickable_mass(options_.config)};
  for (const auto& [id, robot] : robots_) {
    if (robot_is_free(robot)) view.free_robots.insert(id);
  }
  return view;
}

std::int64_t FleetServer::add_orders(std::vector<Order> drafts) {
  std::int64_t first = 0;
  for (Order& draft : drafts) {
    const Order& order = book_.create(std::move(draft), clock_.now());
    if (first == 0) first = order.id;
    if (order.lines.empty()) {
      log_->info("order {} created: {} {} -> {} (request {})", order.id, orders::to_string(order.kind), order.pick_area,
                 order.drop_area, order.request_id);
    } else {
      const int boxes = orders::boxes_of(order);
      const std::size_t lines = orders::parse_pick_lines(order.lines, "pick tour").size();
      log_->info("order {} created: pick tour of {} box{} from {} line{} to {} (request {})", order.id, boxes,
                 boxes == 1 ? "" : "es", lines, lines == 1 ? "" : "s", order.drop_area, order.request_id);
    }
    publish_order(order);  // stored before the requester hears of it
  }
  return first;
}

void FleetServer::handle_commands() {
  command_reader_.take_data([&](model::Command&& command) {
    execute(command, [this](const model::RequestReply& answer) { reply(answer); });
  });
}

void FleetServer::execute(const model::Command& command, const Answer& answer) {
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
      error = begin_map_switch(command, answer);
      if (error.empty()) return;  // answered once the switch is done
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
    } else if (const auto why = orders::why_unseen(command.target, registered_robots())) {
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
  answer({command.request_id, error.empty(), 0, error});
}

bool FleetServer::robot_is_free(const RobotEntry& robot) const {
  constexpr double kRejectionBackoffWall = 2.0;
  if (!robot.registered || robot.lost) return false;
  if (auto r = rejected_at_wall_.find(robot.id);
      r != rejected_at_wall_.end() && SimClock::wall_now() - r->second < kRejectionBackoffWall) {
    return false;
  }
  // On its way home or parking there (a stacker reversing into its bay) a robot takes new work.
  const auto& state = robot.last.task_state;
  if (state != "IDLE" && state != "GO_HOME" && state != "PARKING") return false;
  if (robot.last.carrying_pallet) return false;
  return book_.open_order_of(robot.id) == nullptr;
}

void FleetServer::create_auto_orders() {
  // [Forklift thesis, section 3]: random orders whenever a forklift is free, from an area holding a
  // pallet to a free one. Robots that carry no pallets (pickers) get pick lists instead.
  const auto& names = known_names();
  const auto can = [&](const std::string& fleet_id, orders::OrderKind kind) {
    if (names.abilities.empty()) return kind == orders::OrderKind::kTransport;
    const auto ability = std::find_if(names.abilities.begin(), names.abilities.end(),
                                      [&](const orders::FleetAbility& a) { return a.fleet_id == fleet_id; });
    return ability != names.abilities.end() &&
           !orders::incapability(*ability, orders::order_steps(kind, "", "")).has_value();
  };
  const auto free_for = [&](orders::OrderKind kind) {
    return std::count_if(robots_.begin(), robots_.end(),
                         [&](const auto& e) { return robot_is_free(e.second) && can(e.second.fleet_id, kind); });
  };
  if (const long free_pickers = free_for(orders::OrderKind::kPick); free_pickers > 0) create_auto_pick(free_pickers);
  const long free_robots = free_for(orders::OrderKind::kTransport);
  if (!orders::auto_transport_wanted(book_, free_robots)) return;
  const auto doable = [&](const std::string& pick, const std::string& drop) {
    if (const auto& packing = options_.site.packing; packing && (!orders::open_to_random_transports(*packing, pick) ||
                                                                 !orders::open_to_random_transports(*packing, drop))) {
      return false;
    }
    return !orders::check_order_request({"", pick, drop, "", "", 0}, names).has_value();
  };
  const auto choice = orders::choose_auto_transport(ledger_, book_, rng_, doable);
  if (!choice) return;
  Order draft;
  draft.request_id = "auto";
  draft.pick_area = choice->pick;
  draft.drop_area = choice->drop;
  orders::fill_steps(draft, names);
  const Order& order = book_.create(std::move(draft), clock_.now());
  log_->info("order {} created automatically: {} -> {}", order.id, order.pick_area, order.drop_area);
  publish_order(order);
}

void FleetServer::dispatch() {
  std::vector<const Order*> queue;
  std::map<std::string, bool> taken;  // place -> a robot's body stands on it, asked once per dispatch
  const orders::PlaceTaken place_taken = [&](const std::string& place_id) {
    const auto [it, asked] = taken.try_emplace(place_id, false);
    if (asked) it->second = robot_on_place(place_id);
    return it->second;
  };
  for (const Order* o : book_.queue()) {
    // A transport waits until its load stands at the pick place, the drop place is free, and no
    // robot stands on either.
    if (o->kind != orders::OrderKind::kTransport || orders::ready_to_dispatch(ledger_, *o, place_taken)) {
      queue.push_back(o);
    }
  }
  if (queue.empty()) return;
  std::vector<orders::FreeRobot> free;
  const auto& names = known_names();
  for (const auto& [id, robot] : robots_) {
    if (!robot_is_free(robot)) continue;
    const auto ability = std::find_if(names.abilities.begin(), names.abilities.end(),
                                      [&](const orders::FleetAbility& a) { return a.fleet_id == robot.fleet_id; });
    if (ability != names.abilities.end()) free.emplace_back(robot.id, robot.fleet_id, *ability);
  }
  if (free.empty()) return;
  const auto start = ServerLoadMeter::Clock::now();
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
  load_meter_.dispatched(ServerLoadMeter::Clock::now() - start);
}

bool FleetServer::robot_on_place(const std::string& place_id) const {
  // Bodies are a few metres long at most: robots farther than this from the place are not shaped.
  constexpr double kNearM = 5.0;
  const auto* area = options_.site.find_area(place_id);
  if (!area) return false;
  for (const auto& [id, robot] : robots_) {
    if (!robot.registered || geometry::distance(robot.last.pose.position(), area->pose.position()) > kNearM) continue;
    if (orders::body_stands_on(body_of(robot), *area, options_.site.approach_distance)) return true;
  }
  return false;
}

double FleetServer::travel_cost(const std::string& robot_id, const std::string& place_id) {
  const auto* area = options_.site.find_area(place_id);
  const auto* home = options_.site.find_home(place_id);
  const auto robot = robots_.find(robot_id);
  if ((!area && !home) || robot == robots_.end()) return std::numeric_limits<double>::infinity();
  // 0.30 m out from the place, the table forklifts' distance, on every site. Measured to the plant's 1.2 m,
  // stackers are offered rack places, and a stacker's route there does not end where it can dock
  // (docs/known-limits.md).
  constexpr double kApproach = 0.30;
  const geometry::Pose2 approach = area ? area->approach_pose(kApproach) : home->pose;
  const auto planner = travel_.find(robot->second.fleet_id);
  if (planner == travel_.end()) return std::numeric_limits<double>::infinity();
  return planner->second.travel(robot->second.last.pose, approach);
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
  if (const auto* drop = options_.site.find_area(order.drop_area)) {
    // A move to a loading area ends where a vehicle stands to handle its load, not on the load.
    msg.drop_pose =
        order.kind == orders::OrderKind::kMove ? drop->approach_pose(options_.site.approach_distance) : drop->pose;
  }
  if (const auto* parking = options_.site.find_home(order.drop_area);
      parking && order.kind == orders::OrderKind::kMove) {
    msg.drop_pose = parking->pose;
  }
  msg.kind = std::string(orders::to_string(order.kind));
  msg.lines = order.lines;
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
  chain_stale_ = true;
  if (orders::is_final(order.status)) {
    // A finished order leaves the latched Order topic, so an agent that restarts never receives
    // it again; OrderInfo keeps the record.
    model::OrderAssignment key;
    key.order_id = order.id;
    order_writer_.unregister(key);
  }
}

}  // namespace fleet::server
