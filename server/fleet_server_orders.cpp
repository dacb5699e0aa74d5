// Order requests and operator commands, dispatch and automatic orders, and what the robots are told.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "model/names.hpp"
#include "orders/command_intake.hpp"
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
    replies_.reply(answer);
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
                          .ledger = site_keeper_.state().ledger,
                          .names = known_names(),
                          .site = options_.site,
                          .parked_at = site_keeper_.state().parked_at,
                          .registered = robots_.registered_ids(),
                          .free_robots = {},
                          .reject_when_busy = options_.config.settings.get_bool("server.reject_when_busy"),
                          .max_pickable_mass = orders::max_pickable_mass(options_.config),
                          .loader_fleet = orders::loader_fleet(options_.config),
                          .loader_pallet_boxes = loader_desk_.layout().pallet_boxes};
  view.reserved = loader_desk_.reserved_places();
  // A loader walk goes on to the nearest place by the pickers' roads.
  for (const auto& fleet : options_.config.fleets) {
    const auto roads = travel_.find(fleet.id);
    if (fleet.robot_type != "picker" || roads == travel_.end()) continue;
    view.place_distance = [this, roads](const std::string& from, const std::string& to) {
      const auto* a = options_.site.find_area(from);
      const auto* b = options_.site.find_area(to);
      if (a == nullptr || b == nullptr) return std::numeric_limits<double>::infinity();
      const double standoff = loader_desk_.layout().item_standoff;
      return roads->second.travel(orders::picker_stop_pose(a->pose, standoff),
                                  orders::picker_stop_pose(b->pose, standoff));
    };
    break;
  }
  const double now_wall = SimClock::wall_now();
  for (const auto& [id, robot] : robots_.entries()) {
    if (dispatcher_.takes_new_work(robot, book_, now_wall)) view.free_robots.insert(id);
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
      log_->info("order {} created: pick {} of {} box{} from {} line{}{} (request {})", order.id,
                 order.loader ? "walk" : "tour", boxes, boxes == 1 ? "" : "es", lines, lines == 1 ? "" : "s",
                 order.loader ? ", onto stackers' pallets" : " to " + order.drop_area, order.request_id);
    }
    wire_.publish(order);  // stored before the requester hears of it
  }
  return first;
}

void FleetServer::handle_commands() {
  command_reader_.take_data([&](model::Command&& command) {
    execute(command, [this](const model::RequestReply& answer) { replies_.reply(answer); });
  });
}

void FleetServer::execute(const model::Command& command, const Answer& answer) {
  const orders::CommandDecision decision = orders::decide_command(command, {.book = book_,
                                                                            .site = options_.site,
                                                                            .maps = options_.maps,
                                                                            .config = options_.config,
                                                                            .robots = robots_,
                                                                            .traffic_on = traffic_ != nullptr});
  std::string error = decision.error;
  switch (decision.action) {
    case orders::CommandAction::kNone:
      break;
    case orders::CommandAction::kCancelOrder: {
      const Order& order = *book_.find(decision.order_id);
      const bool was_assigned = !order.robot_id.empty() && order.status != OrderStatus::kQueued;
      if (book_.transition(order.id, OrderStatus::kCancelled, clock_.now(), "cancelled by operator") !=
          TransitionResult::kApplied) {
        error = "order " + command.target + " is already " + std::string(orders::to_string(order.status));
        break;
      }
      log_->info("order {} cancelled by operator", order.id);
      wire_.publish(order);
      if (was_assigned) wire_.withdraw(order, order.robot_id);
      break;
    }
    case orders::CommandAction::kSwitchObstacle: {
      const auto* obstacle = options_.site.find_obstacle(command.target);
      site_keeper_.switch_obstacle(*obstacle, options_.site.name, decision.on);
      log_->info("static obstacle {} {}", command.target, command.value);
      break;
    }
    case orders::CommandAction::kMapOneRobot:
      map_writer_.write({command.target, command.value});
      log_->info("robot {} switched to map '{}'", command.target, command.value);
      break;
    case orders::CommandAction::kSwitchMap:
      error = begin_map_switch(command, answer);
      if (error.empty()) return;  // answered once the switch is done
      break;
    case orders::CommandAction::kAutoOrders:
      auto_orders_.set_on(decision.on);
      log_->info("automatic orders {}", command.value);
      break;
    case orders::CommandAction::kPauseRobot:
      control_writer_.write({command.target, decision.on});
      log_->info("robot {} {}d by operator", command.target, command.verb);
      break;
  }
  if (!error.empty()) log_->warn("command {} {} {} refused: {}", command.verb, command.target, command.value, error);
  answer({command.request_id, error.empty(), 0, error});
}

void FleetServer::create_auto_orders() {
  // Pick tours are in the book before a transport is drawn, so it does not take their places.
  if (auto tours = auto_orders_.pick_tours(intake_view()); !tours.empty()) add_orders(std::move(tours));
  if (auto transport = auto_orders_.transport(intake_view())) add_orders({std::move(*transport)});
}

void FleetServer::dispatch() {
  std::map<std::string, bool> taken;  // place -> a robot's body stands on it, asked once per dispatch
  const orders::PlaceTaken place_taken = [&](const std::string& place_id) {
    const auto [it, asked] = taken.try_emplace(place_id, false);
    if (asked) {
      const auto* area = options_.site.find_area(place_id);
      it->second = area && robots_.someone_stands_on(*area, options_.site.approach_distance);
    }
    return it->second;
  };
  const auto start = ServerLoadMeter::Clock::now();
  const orders::DispatchRound round{
      .book = book_,
      .ledger = site_keeper_.state().ledger,
      .robots = robots_.entries(),
      .abilities = known_names().abilities,
      .place_taken = place_taken,
      .cost = [&](const std::string& robot_id, const std::string& area_id) { return travel_cost(robot_id, area_id); },
      .now_wall = SimClock::wall_now(),
      .held = [&](const Order& order) { return !loader_desk_.ready_for_picker(order); }};
  const auto assignments = dispatcher_.round(round);
  if (assignments.empty()) return;
  for (const auto& assignment : assignments) {
    if (book_.assign(assignment.order_id, assignment.robot_id, clock_.now()) != TransitionResult::kApplied) continue;
    const Order& order = *book_.find(assignment.order_id);
    log_->info("order {} assigned to {}", order.id, order.robot_id);
    watch_.assigned(order.id);
    wire_.publish(order);
    wire_.assign(order);
  }
  load_meter_.dispatched(ServerLoadMeter::Clock::now() - start);
}

double FleetServer::travel_cost(const std::string& robot_id, const std::string& place_id) {
  const auto* area = options_.site.find_area(place_id);
  const auto* home = options_.site.find_home(place_id);
  const auto robot = robots_.entries().find(robot_id);
  if ((!area && !home) || robot == robots_.entries().end()) return std::numeric_limits<double>::infinity();
  // 0.30 m out from the place, the table forklifts' distance, on every site. Measured to the plant's 1.2 m,
  // stackers are offered rack places, and a stacker's route there does not end where it can dock
  // (docs/known-limits.md).
  constexpr double kApproach = 0.30;
  const geometry::Pose2 approach = area ? area->approach_pose(kApproach) : home->pose;
  const auto planner = travel_.find(robot->second.fleet_id);
  if (planner == travel_.end()) return std::numeric_limits<double>::infinity();
  return planner->second.travel(robot->second.last.pose, approach);
}

}  // namespace fleet::server
