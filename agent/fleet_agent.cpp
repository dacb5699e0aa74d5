#include "agent/fleet_agent.hpp"

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"
#include "common/paths.hpp"
#include "common/process_memory.hpp"
#include "model/traffic_requests.hpp"
#include "orders/pick_lines.hpp"

namespace fleet::agent {

namespace {
constexpr double kMaxSleepWall = 0.02;       // the main loop's longest sleep between control steps
constexpr double kViewsStaleWall = 0.5;      // wall seconds without a NeighbourView: read SimTruth itself
constexpr double kMaxPublishHzWall = 100.0;  // RobotState and SimTruth, capped in wall rate at high time scales

}  // namespace

FleetAgent::FleetAgent(AgentOptions options, Logger log)
    : options_(std::move(options)),
      log_(std::move(log)),
      clock_(options_.time_scale),
      fleet_(options_.config.find_robot(options_.robot_id)->first),
      robot_(robot::make_robot(
          *fleet_, options_.config, options_.site,
          options_.site->site.find_home(options_.config.find_robot(options_.robot_id)->second->home)->pose,
          options_.seed, robot::noise_stream_of(options_.robot_id))),
      map_loader_(options_.config, *fleet_, maps_dir()),
      step_lag_(robot_->step_period()),
      participant_(options_.domain),
      // Its own messages in its own partition: DDS Security grants a robot that partition alone.
      state_writer_(participant_, dds::qos::robot_state(), model::robot_partition(options_.robot_id)),
      truth_writer_(participant_, dds::qos::live_state(), model::robot_partition(options_.robot_id)),
      report_writer_(participant_, dds::qos::latched_state(), model::robot_partition(options_.robot_id)),
      path_writer_(participant_, dds::qos::live_state(), model::robot_partition(options_.robot_id)),
      traffic_writer_(participant_, dds::qos::live_state(), model::robot_partition(options_.robot_id)),
      progress_writer_(participant_, dds::qos::live_state(), model::robot_partition(options_.robot_id)),
      grant_reader_(participant_, dds::qos::live_state(), model::robot_partition(options_.robot_id)),
      order_reader_(participant_, dds::qos::latched_state()),
      map_reader_(participant_, dds::qos::latched_state()),
      obstacle_reader_(participant_, dds::qos::latched_state()),
      control_reader_(participant_, dds::qos::latched_state()),
      pallet_reader_(participant_, dds::qos::latched_state()),
      neighbour_reader_(participant_, dds::qos::live_state(), model::robot_partition(options_.robot_id)),
      waitset_(participant_) {
  map_id_ = options_.site->site.name;
  traffic_ = options_.config.settings.get_bool("traffic.enabled");
  pose_delay_s_ = options_.config.settings.get_double("faults.pose_delay_ms") / 1000.0;
  pose_jitter_s_ = options_.config.settings.get_double("faults.pose_delay_jitter_ms") / 1000.0;
  delay_rng_.seed(options_.seed * 31 + robot::noise_stream_of(options_.robot_id));
  if (pose_delay_s_ > 0.0) {
    log_->warn("fault injection: RobotState published {:.0f} +- {:.0f} ms late", pose_delay_s_ * 1000.0,
               pose_jitter_s_ * 1000.0);
  }
  for (dds_entity_t reader : {order_reader_.handle(), map_reader_.handle(), obstacle_reader_.handle(),
                              control_reader_.handle(), pallet_reader_.handle(), grant_reader_.handle()}) {
    waitset_.attach(reader);
  }
  const geometry::Pose2 home = robot_->status().truth;
  log_->info("{} of fleet '{}' at home ({:.2f}, {:.2f}, {:.2f}) on site '{}', DDS domain {}", fleet_->robot_type,
             fleet_->id, home.x, home.y, home.yaw, options_.site->site.name, options_.domain);
}

std::optional<model::OrderReport> FleetAgent::report(const std::string& status, const std::string& reason,
                                                     int pallet_id, const geometry::Pose2& pallet_pose) {
  if (!order_) return std::nullopt;
  const auto& a = order_->assignment;
  const int carried = robot_->status().carried_load;
  const int pallet = pallet_id >= 0 ? pallet_id : carried;
  const model::OrderReport message{a.order_id,   options_.robot_id, status, reason,     a.update_id,
                                   clock_.now(), carried >= 0,      pallet, pallet_pose};
  report_writer_.write(message);
  return message;
}

void FleetAgent::finish_order(const std::string& status, const std::string& reason, int pallet_id,
                              const geometry::Pose2& pallet_pose) {
  // Order reports are latched so a restarted server learns how its orders ended; only the most
  // recent ones need to stay, which keeps the writer's history bounded.
  if (auto final_report = report(status, reason, pallet_id, pallet_pose)) {
    if (const auto dropped = intake_.remember_end(*final_report)) report_writer_.unregister(*dropped);
  }
  order_.reset();
}

std::string FleetAgent::item_stops(const model::OrderAssignment& assignment, std::vector<task::ItemStop>& stops) const {
  std::vector<orders::PickLine> lines;
  try {
    lines = orders::parse_pick_lines(assignment.lines, "order " + std::to_string(assignment.order_id));
  } catch (const InputError& e) {
    return e.what();
  }
  for (const orders::PickLine& l : lines) {
    const map::LoadingArea* area = options_.site->site.find_area(l.place);
    if (area == nullptr) return "order " + std::to_string(assignment.order_id) + ": unknown place " + l.place;
    stops.push_back({l.place, area->pose, l.item, l.quantity});
  }
  return "";
}

void FleetAgent::handle_orders() {
  order_reader_.take_data([&](model::OrderAssignment&& assignment) {
    if (assignment.robot_id != options_.robot_id) return;
    std::optional<orders::RunningOrder> running;
    if (order_) running = orders::RunningOrder{order_->assignment.order_id, order_->assignment.update_id};
    switch (intake_.classify(assignment, running)) {
      case orders::IntakeStep::kIgnore:
        return;
      case orders::IntakeStep::kRepeatFinalReport: {
        const model::OrderReport* ended = intake_.final_report(assignment.order_id);
        log_->info("order {} offered again, already {}: repeating the report", assignment.order_id, ended->status);
        report_writer_.write(*ended);
        return;
      }
      case orders::IntakeStep::kWithdraw:
        withdraw(assignment.order_id);
        return;
      case orders::IntakeStep::kAcknowledgeAgain:
        if (assignment.update_id > order_->assignment.update_id) update_running_order(assignment);
        // Re-sent because our acknowledgement was lost or the server restarted, or updated:
        // acknowledge again and repeat where we are.
        order_->assignment.update_id = assignment.update_id;
        report("ACCEPTED");
        if (!order_->phase.empty()) report(order_->phase);
        return;
      case orders::IntakeStep::kConsider:
        consider(assignment);
        return;
    }
  });
}

void FleetAgent::update_running_order(const model::OrderAssignment& assignment) {
  // What an update may change: a loader walk's release (more stops, a new transporter behind
  // it); where a transport with no drop area yet stands with its load, or its drop area.
  const model::OrderAssignment& running = order_->assignment;
  const bool loader = assignment.loader && running.loader;
  const bool transport = running.drop_area.empty() && (assignment.stand || !assignment.drop_area.empty());
  if (!loader && !transport) return;
  task::TaskOrder update{std::to_string(assignment.order_id),
                         assignment.pick_area,
                         assignment.pick_pose,
                         assignment.drop_area,
                         assignment.drop_pose,
                         loader ? orders::OrderKind::kPick : orders::OrderKind::kTransport};
  update.loader = loader;
  update.released = assignment.released_stops;
  update.approach = assignment.approach_stops;
  update.pallet = assignment.pallet;
  update.stand = assignment.stand;
  std::string why;
  if (!robot_->submit(update, &why)) {
    log_->warn("order {}: update {} not taken: {}", assignment.order_id, assignment.update_id, why);
    return;
  }
  order_->assignment = assignment;
  if (loader) {
    log_->info("order {} updated: {} stop{} released, {} to drive to, pallet {} behind", assignment.order_id,
               assignment.released_stops, assignment.released_stops == 1 ? "" : "s",
               std::max(assignment.released_stops, assignment.approach_stops), assignment.pallet);
  } else {
    log_->info("order {} updated: {}", assignment.order_id,
               assignment.drop_area.empty() ? std::string("stand elsewhere with the load")
                                            : "drop at " + assignment.drop_area);
  }
}

void FleetAgent::withdraw(std::int64_t order_id) {
  if (robot_->withdraw()) {
    log_->warn("order {} withdrawn by the server", order_id);
    // Its last report is latched: a restarted server would hear the order running here still
    // and withdraw it again, from a robot long on other orders.
    model::OrderReport instance;
    instance.order_id = order_id;
    report_writer_.unregister(instance);
    order_.reset();
  } else {
    // Withdrawn while it was lost, the order was re-queued; the robot lifted the pallet before
    // the withdrawal reached it. It carries the order on and says so: the server hands the order
    // back to the robot that has the pallet.
    log_->warn("order {} withdrawn by the server after the pallet was lifted: carrying it on", order_id);
  }
}

void FleetAgent::consider(const model::OrderAssignment& assignment) {
  const auto kind = orders::parse_kind(assignment.kind.empty() ? "transport" : assignment.kind);
  task::TaskOrder task_order{std::to_string(assignment.order_id),
                             assignment.pick_area,
                             assignment.pick_pose,
                             assignment.drop_area,
                             assignment.drop_pose,
                             kind.value_or(orders::OrderKind::kTransport)};
  task_order.loader = assignment.loader;
  task_order.released = assignment.released_stops;
  task_order.approach = assignment.approach_stops;
  task_order.pallet = assignment.pallet;
  task_order.stand = assignment.stand;
  orders::NewOrderChecks checks;
  if (!kind) {
    checks.invalid = "unknown order kind '" + assignment.kind + "'";
  } else if (kind == orders::OrderKind::kPick) {
    checks.invalid = item_stops(assignment, task_order.items);
  }
  if (order_) checks.busy_with = order_->assignment.order_id;
  if (kind) checks.robot_refusal = robot_->refusal(*kind);
  checks.paused = paused_;
  std::string why = orders::AssignmentIntake::refusal_of(checks);
  if (why.empty() && robot_->submit(task_order, &why)) {
    order_ = CurrentOrder{assignment, ""};
    log_->info("order {} accepted: {} -> {}", assignment.order_id, assignment.pick_area, assignment.drop_area);
    report("ACCEPTED");
    return;
  }
  log_->warn("rejecting order {}: {}", assignment.order_id, why);
  report_writer_.write({assignment.order_id,
                        options_.robot_id,
                        "REJECTED",
                        why,
                        assignment.update_id,
                        clock_.now(),
                        robot_->status().carried_load >= 0,
                        -1,
                        {}});
}

void FleetAgent::handle_site_inputs() {
  map_reader_.take_data([&](model::MapAssignment&& assignment) {
    if (assignment.robot_id != options_.robot_id) return;
    if (assignment.map_id == map_id_ && map_loader_.pending().empty()) return;
    map_loader_.request(assignment.map_id);
  });
  if (auto loaded = map_loader_.take()) switch_map(std::move(*loaded));
  control_reader_.take_data([&](model::RobotControl&& control) {
    if (control.robot_id != options_.robot_id || control.paused == paused_) return;
    paused_ = control.paused;
    robot_->set_paused(paused_);
    log_->info("{} by the operator", paused_ ? "paused" : "resumed");
  });
  obstacle_reader_.take_data([&](model::StaticObstacleState&& obstacle) {
    // Obstacles of every map the server serves arrive; the ones of other maps wait in the cache
    // until this robot is switched to their map.
    obstacle_cache_[{obstacle.map_id, obstacle.obstacle_id}] = obstacle.enabled;
    if (!obstacle.map_id.empty() && obstacle.map_id != map_id_) return;
    auto it = obstacles_.find(obstacle.obstacle_id);
    if (it == obstacles_.end() || it->second != obstacle.enabled) {
      log_->info("static obstacle {} {}", obstacle.obstacle_id, obstacle.enabled ? "enabled" : "disabled");
    }
    obstacles_[obstacle.obstacle_id] = obstacle.enabled;
    if (robot_->set_obstacle(obstacle.obstacle_id, obstacle.enabled)) {
      log_->info("replanning {} after obstacle {} was {}",
                 order_ ? "order " + std::to_string(order_->assignment.order_id) : "the way home", obstacle.obstacle_id,
                 obstacle.enabled ? "enabled" : "disabled");
    }
  });
  bool pallets_changed = false;
  pallet_reader_.take_data([&](model::PalletTruth&& pallet) {
    pallets_changed = true;
    pallets_[pallet.pallet_id] = std::move(pallet);
  });
  if (pallets_changed) {
    std::map<int, geometry::Pose2> standing;
    for (const auto& [id, p] : pallets_) {
      if (p.carried_by.empty()) standing[id] = p.pose;
    }
    robot_->set_standing_loads(standing);
    log_->debug("{} pallets standing, {} known", standing.size(), pallets_.size());
  }
}

void FleetAgent::switch_map(LoadedMap loaded) {
  // [Forklift thesis, section 3]: the map is assigned by the server at the start and whenever the user
  // changes it. Only a revision of the same site can be driven without moving the robot.
  const std::string& map_id = loaded.map_id;
  if (map_id == map_id_) return;  // switched back before the other map was read
  if (!loaded.site) {
    log_->error("map '{}' assigned but cannot be loaded, staying on '{}': {}", map_id, map_id_, loaded.error);
    return;
  }
  const auto& next = loaded.site;
  if (const std::string why = map::revision_mismatch(robot_->navigation().site().site, next->site); !why.empty()) {
    log_->error("map '{}' assigned, staying on '{}': {}", map_id, map_id_, why);
    return;
  }
  robot_->set_site(next, std::move(loaded.route_graph));
  log_->info("map switched from '{}' to '{}': {} graph points; replanning", map_id_, map_id,
             next->graph.graph.points.size());
  map_id_ = map_id;
  obstacles_.clear();
  for (const auto& [key, enabled] : obstacle_cache_) {
    if (key.first != map_id_) continue;
    obstacles_[key.second] = enabled;
    robot_->set_obstacle(key.second, enabled);
  }
}

void FleetAgent::take_true_bodies(std::optional<model::NeighbourView>& latest) {
  // Simulation only: what the sensors see. The server relays the true bodies near this robot in
  // its NeighbourView. While no view comes (the server is down), the agent reads every robot's
  // SimTruth itself, so that its simulated lidar does not lose sight of robots that move on.
  const double now_wall = SimClock::wall_now();
  bool changed = false;
  if (latest) {
    last_view_wall_ = now_wall;
    if (direct_truths_) {
      direct_truths_.reset();
      log_->info("NeighbourViews are back: the true bodies come from them again");
    }
    // A complete view holds every body near this one; the first views of a server that just
    // started lack those it has not heard from yet.
    if (latest->complete) truths_.clear();
    for (auto& body : latest->bodies) {
      if (body.robot_id != options_.robot_id && geometry::is_finite(body.pose))
        truths_[body.robot_id] = std::move(body);
    }
    changed = true;
  } else if (!direct_truths_ && now_wall - last_view_wall_ > kViewsStaleWall) {
    direct_truths_ = std::make_unique<dds::Reader<model::SimTruth>>(participant_, dds::qos::live_state(),
                                                                    dds::robot_report_partitions());
    log_->info("no NeighbourView for {:.1f} s: reading every robot's SimTruth until views come again", kViewsStaleWall);
  }
  if (direct_truths_) {
    direct_truths_->take_data([&](model::SimTruth&& truth) {
      if (truth.robot_id == options_.robot_id || !geometry::is_finite(truth.pose)) return;
      truths_[truth.robot_id] = std::move(truth);
      changed = true;
    });
  }
  if (!changed) return;
  std::vector<geometry::Polygon> footprints;
  for (const auto& [id, t] : truths_) footprints.push_back(geometry::footprint_polygon(t.pose, t.footprint));
  robot_->navigation().set_true_neighbours(std::move(footprints));
}

void FleetAgent::handle_fleet_view(double now_sim) {
  std::optional<model::NeighbourView> latest;
  neighbour_reader_.take_data([&](model::NeighbourView&& view) {
    if (view.robot_id == options_.robot_id && view.map_id == map_id_) latest = std::move(view);
  });
  take_true_bodies(latest);
  if (!latest) return;
  std::vector<robot::Neighbour> listed;
  for (const auto& r : latest->robots) {
    if (r.robot_id == options_.robot_id) continue;
    if (!geometry::is_finite(r.pose)) continue;
    // A robot the server has marked lost is a stopped body at its last pose (its drives stop
    // with its software): a fixed obstacle, not one growing with the age of its data.
    const bool lost = r.task_state == "LOST";
    listed.push_back({r.robot_id, r.pose, r.footprint, lost ? 0.0 : std::abs(r.speed),
                      lost ? 0.0 : std::max(0.0, now_sim - r.sim_time)});
  }
  // Robots missing from this view stay where last listed: the first views of a server that just
  // restarted lack the robots it has not heard from yet. A complete view shows who has left the
  // radius it covers.
  if (latest->complete) {
    neighbours_.update_within(listed, now_sim, robot_->status().estimate.position(), latest->radius);
  } else {
    neighbours_.update(listed, now_sim);
  }
  robot_->navigation().set_neighbours(neighbours_.current());
}

void FleetAgent::handle_events() {
  for (const auto& e : robot_->take_events()) {
    using K = robot::RobotEvent::Kind;
    switch (e.kind) {
      case K::kPhase:
        if (!order_) break;
        order_->phase = e.text;
        log_->info("order {}: {}", order_->assignment.order_id, e.text);
        report(e.text);
        break;
      case K::kLifted:
        log_->info("load {} taken up", e.load_id);
        break;
      case K::kDone:
        if (!order_) break;
        if (order_->assignment.kind == "pick") {
          log_->info("order {} done: boxes put down at {}", order_->assignment.order_id, order_->assignment.drop_area);
        } else if (e.load_id < 0) {
          log_->info("order {} done: parked at {}", order_->assignment.order_id, order_->assignment.drop_area);
        } else {
          log_->info("order {} done: load {} put down at {} ({:.3f}, {:.3f}, {:.3f})", order_->assignment.order_id,
                     e.load_id, order_->assignment.drop_area, e.load_pose.x, e.load_pose.y, e.load_pose.yaw);
        }
        finish_order("DONE", "", e.load_id, e.load_pose);
        break;
      case K::kAreaEmpty:
      case K::kFailed:
        if (!order_) break;
        log_->warn("order {} failed: {}", order_->assignment.order_id, e.text);
        finish_order("FAILED", e.text);
        break;
      case K::kHome:
        log_->info("home");
        break;
      case K::kState:
        break;
    }
  }
}

void FleetAgent::publish_state(double now_sim) {
  model::RobotState state;
  state.robot_id = options_.robot_id;
  state.fleet_id = fleet_->id;
  state.map_id = map_id_;
  const robot::RobotStatus status = robot_->status();
  state.pose = status.estimate;
  state.covariance = status.covariance;
  state.localization_score = status.localization_score;
  state.speed = status.command.vx;
  state.yaw_rate = status.command.omega;
  state.task_state = status.task_state;
  state.detail = status.detail;
  state.order_id = order_ ? order_->assignment.order_id : 0;
  state.carrying_pallet = status.carried_load >= 0;
  state.sim_time = now_sim;
  state.walk_stop = status.walk_stop;
  state.boxes_loaded = status.boxes_loaded;
  robot::DockingView docking = robot_->docking_view();
  state.docking_targets = std::move(docking.targets);
  state.detected_pallet = docking.detected_pallet;
  const StepLagMeter::Figures lag = step_lag_.figures();
  state.control_lag_p50 = lag.p50_s;
  state.control_lag_p99 = lag.p99_s;
  state.control_period = step_lag_.period();
  state.control_steps_skipped = lag.skipped;
  if (pose_delay_s_ > 0.0) {
    // A slow network: the state is stamped now and arrives late.
    std::uniform_real_distribution<double> jitter(-pose_jitter_s_, pose_jitter_s_);
    const double delay = std::max(0.0, pose_delay_s_ + jitter(delay_rng_));
    delayed_states_.emplace_back(SimClock::wall_now() + delay, state);
  } else {
    state_writer_.write(state);
  }
  truth_writer_.write({options_.robot_id, status.truth, status.footprint, state.carrying_pallet, now_sim});
  if (state.task_state != last_state_) {
    log_->info("state {}{}", state.task_state, state.detail.empty() ? "" : " (" + state.detail + ")");
    last_state_ = state.task_state;
  } else if (state.detail != last_detail_ && !state.detail.empty()) {
    log_->debug("state {} ({})", state.task_state, state.detail);
  }
  last_detail_ = state.detail;
  if (robot_->navigation().follower().path().size() != last_path_size_) {
    path_writer_.write({options_.robot_id, robot_->navigation().follower().path(), now_sim});
    last_path_size_ = robot_->navigation().follower().path().size();
  }
}

void FleetAgent::flush_delayed_states() {
  // Keyed keep-last delivery: several late states may fall due at once; each is still written,
  // in order, as a late network would deliver them.
  const double now = SimClock::wall_now();
  while (!delayed_states_.empty() && delayed_states_.front().first <= now) {
    state_writer_.write(delayed_states_.front().second);
    delayed_states_.pop_front();
  }
}

void FleetAgent::publish_traffic(double now_sim) {
  if (!traffic_) return;
  robot::TrafficRoute route = robot_->traffic_route();
  // The route goes out at once when it changes, and once a second besides, so that a server that
  // missed it (restarted, or the sample lost under later ones) has it again; between those, only
  // the progress along it, at the state rate (the caller's): a route of a few hundred points at
  // that rate filled a 2 Mbit/s link. A route left (parked off the road) goes out once; a work
  // area with every sample, until the server has answered and after; an area to keep clear
  // (docked) as a route does.
  const bool changed = route.version != last_traffic_.version || route.points != last_traffic_.points ||
                       route.work_area != last_traffic_.work_area || route.arrival_area != last_traffic_.arrival_area ||
                       route.keep_clear != last_traffic_.keep_clear || map_id_ != last_traffic_map_;
  if (!changed && now_sim == last_traffic_sim_) return;
  if (!changed && route.points.empty() && route.work_area.empty() && route.keep_clear.empty() &&
      last_traffic_.points.empty() && last_traffic_sim_ >= 0.0) {
    return;
  }
  const double now_wall = SimClock::wall_now();
  if (changed || now_wall - last_route_sent_wall_ >= model::kRouteRepeatWallS) {
    traffic_writer_.write({options_.robot_id, route.version, route.points, route.progress, route.stopped_for, now_sim,
                           route.work_area, route.arrival_area, route.keep_clear, map_id_});
    last_route_sent_wall_ = now_wall;
  } else {
    progress_writer_.write({options_.robot_id, route.version, route.progress, route.stopped_for, now_sim, map_id_});
  }
  last_traffic_ = std::move(route);
  last_traffic_map_ = map_id_;
  last_traffic_sim_ = now_sim;
}

void FleetAgent::handle_traffic() {
  if (!traffic_) return;
  grant_reader_.take_data([&](model::TrafficGrant&& grant) {
    if (grant.robot_id != options_.robot_id || grant.sim_time < grants_valid_from_sim_) return;
    robot_->set_traffic_grant(robot::permit_of(std::move(grant)));
  });
}

void FleetAgent::drop_grant(double now_sim) {
  if (!traffic_) return;
  grants_valid_from_sim_ = now_sim;
  robot::TrafficPermit none;
  none.version = robot_->traffic_route().version;
  none.granted_index = -1;  // no grant for this route: the robot stands
  robot_->set_traffic_grant(none);
  log_->warn(
      "stood still for longer than the server waits before it takes a robot for lost: standing until the "
      "traffic manager grants the road again");
}

void FleetAgent::run(const std::atomic<bool>& stop) {
  const double step = robot_->step_period();
  const double publish_period_wall =
      std::max(1.0 / kMaxPublishHzWall, clock_.to_wall(1.0 / options_.config.settings.get_double("agent.state_hz")));
  // The robot keeps its own sim time from zero; `offset` maps it onto the shared clock.
  double offset = clock_.now() - robot_->time();
  double last_publish_wall = 0.0;
  double target = clock_.now();
  publish_state(target);
  ProcessMemory memory;
  // Half the server's silence limit: a stop that long may have cost the robot its grants.
  const double grant_lost_gap_wall = 0.5 * options_.config.settings.get_double("server.robot_lost_after_s");
  double last_loop_wall = SimClock::wall_now();
  const auto publish_when_due = [&](double sim_time) {
    const double now_wall = SimClock::wall_now();
    if (now_wall - last_publish_wall < publish_period_wall) return false;
    publish_state(sim_time);
    publish_traffic(sim_time);
    last_publish_wall = now_wall;
    return true;
  };
  while (!stop.load()) {
    // Asleep until the next control step is due or an input arrives (the grants, orders and site
    // inputs wake the waitset): a fixed short timeout woke the process hundreds of times a second
    // for nothing, a fifth of an idle agent's CPU.
    const double until_step_wall = clock_.to_wall(robot_->time() + offset + step - clock_.now());
    waitset_.wait(std::chrono::microseconds(static_cast<long>(std::clamp(until_step_wall, 0.0, kMaxSleepWall) * 1e6)));
    const double loop_wall = SimClock::wall_now();
    if (loop_wall - last_loop_wall >= grant_lost_gap_wall) drop_grant(clock_.now());
    last_loop_wall = loop_wall;
    handle_site_inputs();
    handle_orders();
    target = clock_.now();
    handle_fleet_view(target);
    // Advance in fixed control steps to the clock. After a long gap (the process was stopped)
    // the body does not replay the missed time: it was frozen with its software.
    double behind = target - (robot_->time() + offset);
    if (behind > 1.0) {
      offset += behind - step;
      step_lag_.steps_skipped(static_cast<std::int64_t>((behind - step) / step));
      behind = step;
    }
    handle_traffic();
    for (; behind >= step; behind -= step) {
      // Late by how far the clock had passed the end of the period this step covers.
      step_lag_.step_ran(behind - step);
      robot_->step();
      handle_events();
      // A long catch-up (a burst of camera frames, a loaded host) still publishes at the state
      // rate, so that the server's liveness deadline sees a robot that is only busy.
      if (behind >= 2.0 * step) publish_when_due(robot_->time() + offset);
    }
    if (!publish_when_due(target) && traffic_ && robot_->navigation().follower().version() != last_traffic_.version) {
      publish_traffic(target);
    }
    flush_delayed_states();
    memory.tick(SimClock::wall_now());
  }
  log_->info("stopping");
}

}  // namespace fleet::agent
