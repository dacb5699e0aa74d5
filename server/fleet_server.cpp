#include "server/fleet_server.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

#include "common/process_memory.hpp"
#include "model/names.hpp"
#include "monitor/order_accounting.hpp"
#include "monitor/robot_health.hpp"
#include "orders/order_info.hpp"
#include "orders/order_request_check.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderStatus;

FleetServer::FleetServer(ServerOptions options, Logger log)
    : options_(std::move(options)),
      log_(std::move(log)),
      store_(options_.db_path),
      clock_(options_.time_scale),
      dispatcher_(orders::make_dispatch_policy(options_.config.settings.get_string("server.dispatch_policy"))),
      auto_orders_(options_.config.settings.get_bool("server.auto_orders"), options_.seed,
                   options_.config.settings.get_string("server.auto_pick_handling")),
      term_{.term = orders::next_term(store_.term(), options_.heard_term),
            .took_over = options_.took_over,
            .since_unix_ms = static_cast<std::int64_t>(SimClock::wall_now() * 1000.0),
            .server_id = options_.server_id},
      participant_(options_.domain, static_cast<std::int32_t>(std::min<std::int64_t>(
                                        orders::strength(term_), std::numeric_limits<std::int32_t>::max()))),
      server_info_writer_(participant_, dds::qos::latched_state()),
      map_writer_(participant_, dds::qos::latched_state()),
      control_writer_(participant_, dds::qos::latched_state()),
      request_reader_(participant_, dds::qos::requests()),
      command_reader_(participant_, dds::qos::requests()),
      robot_state_reader_(participant_, dds::qos::robot_state(), dds::robot_report_partitions()),
      order_report_reader_(participant_, dds::qos::latched_state(), dds::robot_report_partitions()),
      handover_reader_(participant_, dds::qos::latched_state()),
      waitset_(participant_),
      load_meter_(participant_, term_),
      peers_(participant_, term_) {
  store_.save_term(term_.term);
  log_->info("serving as the active server {} in term {}", term_.server_id, term_.term);
  for (dds_entity_t reader : {request_reader_.handle(), command_reader_.handle(), robot_state_reader_.handle(),
                              routing_.path_reader(), order_report_reader_.handle()}) {
    waitset_.attach(reader);
  }
  adopt(derive_site(options_.site_map, options_.config));
  if (!traffic_) {
    log_->info("traffic control off: robots avoid each other only locally (the Forklift thesis's behaviour)");
  }
  if (options_.maps.empty()) options_.maps = {options_.site.name};
  log_->info("maps of site '{}': {}", options_.site.name, model::join(options_.maps));
  started_wall_ = SimClock::wall_now();
  site_keeper_.restore(options_.site, options_.config);
  restore_orders();
  recovery_.hold_unheard_robots();
  // [Forklift thesis, section 3]: the map is assigned at the start; obstacles are forwarded when they
  // change and when robots start (latched topics give late joiners the current set).
  for (const auto& [fleet, robot] : options_.config.all_robots()) control_writer_.write({robot->id, false});
  publish_map_and_obstacles();
  publish_server_info();
  log_->info("serving site '{}' on DDS domain {} at time scale {}, dispatch '{}', automatic orders {}",
             options_.site.name, options_.domain, options_.time_scale,
             options_.config.settings.get_string("server.dispatch_policy"), auto_orders_.on() ? "on" : "off");
}

FleetServer::~FleetServer() = default;

void FleetServer::restore_orders() {
  const auto stored = store_.load_all();
  // A takeover begins the ids of its term's block: a server cut off from this one goes on in the
  // block of an earlier term, and the two never hand out one id.
  book_ = orders::OrderBook(term_.took_over ? std::max(store_.next_id(), orders::first_order_id(term_.term))
                                            : store_.next_id());
  long open = 0;
  for (Order order : stored) {
    orders::fill_steps(order, known_names());
    book_.restore(order);
    if (orders::is_final(order.status)) {
      wire_.announce(order);
      continue;
    }
    ++open;
    if (order.status != OrderStatus::kQueued) {
      // Assigned before the restart: offer it to its robot again. A robot still working on it
      // acknowledges and goes on; its latched OrderState tells us how far it got, also if it
      // finished while we were down.
      wire_.assign(order);
    }
    wire_.announce(order);
  }
  if (!stored.empty() || term_.took_over) {
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
  info.started_unix_ms = static_cast<std::int64_t>(started_wall_ * 1000.0);
  info.refused_samples = gate_.refused();
  info.refused_senders = gate_.refused_senders();
  server_info_writer_.write(info);
}

void FleetServer::publish_map_and_obstacles() {
  for (const auto& [fleet, robot] : options_.config.all_robots()) map_writer_.write({robot->id, options_.site.name});
  site_keeper_.publish_obstacles(options_.site);
}

std::string FleetServer::begin_map_switch(const model::Command& command, Answer answer) {
  if (map_switch_) return "the switch to map '" + map_switch_->map_id + "' is under way: send it again once it is done";
  // Copies: the derivation runs on its own thread while the loop goes on with the current ones.
  map_switch_ = MapSwitch{command.request_id, command.value,
                          std::async(std::launch::async, load_revision, options_.site, command.value, options_.config),
                          std::move(answer)};
  log_->info("switching to map '{}': deriving its graphs and traffic zones", command.value);
  return "";
}

void FleetServer::adopt(SiteDerivation derived) {
  options_.site_map = std::move(derived.site_map);
  options_.site = options_.site_map->site;
  known_names_ = std::move(derived.known_names);
  travel_ = std::move(derived.travel);
  // Routes on the old graph mean nothing on the new one: every agent replans and enters anew.
  traffic_.reset();
  if (derived.traffic) {
    traffic_ =
        std::make_unique<TrafficControl>(std::move(derived.traffic), options_.site.name, participant_, gate_, log_);
  } else if (derived.places) {
    traffic_ =
        std::make_unique<PlaceTrafficControl>(std::move(derived.places), options_.site.name, participant_, gate_, log_);
  }
}

void FleetServer::finish_map_switch() {
  if (!map_switch_ || map_switch_->derived.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
  MapSwitch done = std::move(*map_switch_);
  map_switch_.reset();
  std::string error;
  try {
    SiteDerivation derived = done.derived.get();
    // Where the robots stand now, not when the switch was asked for.
    std::map<std::string, geometry::Vec2> standing;
    for (const auto& [id, robot] : robots_.entries()) {
      if (robot.registered) standing[id] = robot.last.pose.position();
    }
    if (options_.site_map) error = robot_on_closed_road(*options_.site_map, *derived.site_map, done.map_id, standing);
    if (error.empty()) {
      const std::string previous = options_.site.name;
      adopt(std::move(derived));
      // Where every robot stands, before any of them enters the new graph.
      for (const auto& [id, robot] : robots_.entries()) {
        if (traffic_ && robot.registered) traffic_->set_body(id, robots_.body_of(robot));  // lost ones too: still there
      }
      site_keeper_.switched_to(options_.site);
      publish_map_and_obstacles();
      publish_server_info();
      log_->info("map switched from '{}' to '{}' for every robot", previous, options_.site.name);
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!error.empty()) log_->warn("command map {} refused: {}", done.map_id, error);
  done.answer({done.request_id, error.empty(), 0, error});
}

RunEnd FleetServer::run(const std::atomic<bool>& stop) {
  // A loop that takes longer than two traffic cycles answers requests late: it says where its
  // time went (debug log), which is what a late grant is read back from.
  constexpr double kSlowLoopWall = 0.1;
  ProcessMemory memory;
  LoopStages stages;
  double last_loop_wall = SimClock::wall_now();
  while (!stop.load()) {
    waitset_.wait(std::chrono::milliseconds(5));
    if (stepped_aside(stop, SimClock::wall_now() - last_loop_wall)) return RunEnd::kSteppedDown;
    last_loop_wall = SimClock::wall_now();
    stages.start();
    handle_order_requests();
    handle_commands();
    finish_map_switch();
    stages.lap("requests");
    handle_robot_states();
    routing_.take_reports(gate_);
    handle_order_reports();
    handle_handed_over_orders();
    stages.lap("states");
    handle_web_requests();
    recovery_.check(SimClock::wall_now(), started_wall_);
    replies_.forget_old();
    stages.lap("web");
    if (traffic_) {
      // Traffic cycles at 20 Hz of sim time, at most 100 Hz of wall time at high time scales.
      const double now_sim = clock_.now();
      const double now_wall = SimClock::wall_now();
      const auto requests_start = ServerLoadMeter::Clock::now();
      traffic_->handle_requests(now_sim, now_wall);
      const auto update_start = ServerLoadMeter::Clock::now();
      load_meter_.requests_taken(update_start - requests_start);
      stages.lap("traffic requests");
      if (now_sim >= next_traffic_sim_ && now_wall - last_traffic_wall_ >= 0.01) {
        traffic_->update(now_sim, now_wall);
        load_meter_.traffic_updated(ServerLoadMeter::Clock::now() - update_start);
        next_traffic_sim_ = now_sim + 0.05;
        last_traffic_wall_ = now_wall;
      }
      stages.lap("traffic update");
    }
    recovery_.check_acknowledgements();
    if (gate_.take_change()) publish_server_info();  // the refusals, for fleetctl stats
    if (auto_orders_.due(SimClock::wall_now())) create_auto_orders();
    advance_packing_chain();
    advance_loader_jobs();
    stages.lap("orders");
    dispatch();
    stages.lap("dispatch");
    routing_.publish_when_due(robots_, options_.site.name);
    stages.lap("views");
    publish_web_snapshot();
    load_meter_.publish_when_due(SimClock::wall_now(), clock_.now(), robots_.registered_count());
    memory.tick(SimClock::wall_now());
    stages.lap("web snapshot");
    if (stages.total_s() > kSlowLoopWall && log_->should_log(spdlog::level::debug)) {
      log_->debug("server loop took {:.0f} ms: {}", stages.total_s() * 1e3, stages.describe());
    }
  }
  log_->info("stopping; {} orders known", book_.all().size());
  return RunEnd::kStopped;
}

bool FleetServer::stepped_aside(const std::atomic<bool>& stop, double since_last_loop_s) {
  // A server whose loop stood still for longer than its liveliness lease (its host froze, its
  // link was cut) may have been taken over meanwhile: before it acts on anything, it listens for
  // one ServerLoad period for an active server that outranks it.
  constexpr double kLeaseS = 1.0;
  constexpr double kListenS = 1.5;
  double listen_until = SimClock::wall_now();
  if (since_last_loop_s > kLeaseS) {
    log_->warn(
        "the server loop stood still for {:.1f} s, longer than its liveliness lease: listening for a server "
        "that took over",
        since_last_loop_s);
    listen_until += kListenS;
  }
  for (;;) {
    if (const auto other = peers_.outranking_active()) {
      log_->warn("stepping down: server {} is active in term {} (this server's term {}); going on as its standby",
                 other->server_id, other->term, term_.term);
      return true;
    }
    if (stop.load() || SimClock::wall_now() >= listen_until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

const orders::KnownNames& FleetServer::known_names() const {
  return *known_names_;
}

void FleetServer::handle_web_requests() {
  if (!bridge_) return;
  for (auto& pending : bridge_->drain()) {
    if (const auto* command = std::get_if<model::Command>(&pending.request)) {
      // A map switch answers later: the promise goes with the answer.
      auto promise = std::make_shared<std::promise<model::RequestReply>>(std::move(pending.reply));
      execute(*command, [promise](const model::RequestReply& reply) { promise->set_value(reply); });
    } else {
      pending.reply.set_value(execute(std::get<model::OrderRequest>(pending.request)));
    }
  }
}

void FleetServer::publish_web_snapshot() {
  constexpr double kWebHzWall = 20.0;
  if (!bridge_) return;
  const double now_wall = SimClock::wall_now();
  if (now_wall - last_web_snapshot_wall_ < 1.0 / kWebHzWall) return;
  last_web_snapshot_wall_ = now_wall;
  LiveSnapshot snap;
  snap.map = options_.site.name;
  snap.site_map = options_.site_map;
  snap.known_names = known_names_;
  snap.sim_time = clock_.now();
  snap.time_scale = options_.time_scale;
  const double lost_after = options_.config.settings.get_double("server.robot_lost_after_s");
  for (const auto& [id, robot] : robots_.entries()) {
    if (!robot.registered) continue;
    RobotView view;
    view.state = robot.last;
    view.truth = routing_.truth_of(id);
    view.path = routing_.path_of(id);
    if (const auto spec = options_.config.find_robot(id)) view.footprint = spec->first->footprint;
    const double silent_wall = now_wall - robot.last_seen_wall;
    view.health = std::string(monitor::to_string(monitor::robot_health(
        {.lost = robot.lost, .stalled = robot.stalled, .silent_s = silent_wall, .lost_after_s = lost_after})));
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
  fill_orders(book_.all(), snap);
  const double hours = (snap.sim_time - started_wall_ * options_.time_scale) / 3600.0;
  snap.orders_per_hour = hours > 0 ? snap.orders_done / hours : 0.0;
  snap.obstacle_enabled = site_keeper_.state().obstacle_enabled;
  snap.pallet_at = site_keeper_.state().ledger.occupancy();
  snap.auto_orders = auto_orders_.on();
  snap.server_id = options_.server_id;
  bridge_->publish(std::move(snap));
}

}  // namespace fleet::server
