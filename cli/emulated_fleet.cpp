#include "cli/emulated_fleet.hpp"

#include <algorithm>
#include <chrono>

#include "dds/qos.hpp"
#include "model/traffic_requests.hpp"
#include "orders/order_kind.hpp"
#include "robot/traffic_follower.hpp"

namespace fleet::cli {

namespace {

double unix_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

/// Final reports kept per robot, to repeat when the server offers a finished order again.
constexpr std::size_t kKeptReports = 8;

}  // namespace

EmulatedFleet::EmulatedFleet(EmulatedFleetOptions options, std::shared_ptr<const map::RoadGraph> graph, Logger log)
    : options_(std::move(options)),
      log_(std::move(log)),
      routes_(std::move(graph)),
      participant_(options_.domain),
      state_writer_(participant_, dds::qos::robot_state()),
      report_writer_(participant_, dds::qos::latched_state()),
      path_writer_(participant_, dds::qos::live_state()),
      traffic_writer_(participant_, dds::qos::live_state()),
      progress_writer_(participant_, dds::qos::live_state()),
      grant_reader_(participant_, dds::qos::live_state(), model::every_robot_partition()),
      order_reader_(participant_, dds::qos::latched_state()),
      pallet_reader_(participant_, dds::qos::latched_state()) {
  const std::uint64_t first_version = robot::first_route_version(std::chrono::system_clock::now());
  robots_.reserve(options_.robots.size());
  for (const auto& [id, home] : options_.robots) {
    index_[id] = robots_.size();
    robots_.emplace_back(id, home, options_.params, first_version);
    neighbour_readers_.push_back(std::make_unique<dds::Reader<model::NeighbourView>>(
        participant_, dds::qos::live_state(), model::robot_partition(id)));
  }
  links_.resize(robots_.size());
}

void EmulatedFleet::run_until(double now_sim) {
  take_pallets();
  take_orders(now_sim);
  take_grants();
  const double step = options_.params.step_s;
  if (sim_ < 0.0 || now_sim - sim_ > 1.0) sim_ = now_sim;  // the start, or a stall not replayed
  for (; sim_ + step <= now_sim; sim_ += step) step_all(sim_);
  const bool due = now_sim >= next_publish_sim_;
  if (due) {
    next_publish_sim_ = now_sim + 1.0 / options_.state_hz;
    for (auto& reader : neighbour_readers_) {
      figures_.samples_in += reader->take_data([](model::NeighbourView&&) {});
    }
  }
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    // A new route goes out at once, as an agent's; the rest at the state rate.
    const bool new_route = robots_[i].route_version() != links_[i].sent_version;
    if (due || new_route) publish(i, now_sim);
  }
  if (now_sim >= next_watch_sim_) {
    next_watch_sim_ = now_sim + 0.1;
    watch(now_sim);
  }
}

void EmulatedFleet::take_pallets() {
  pallet_reader_.take_data([&](model::PalletTruth&& pallet) {
    std::erase_if(load_at_, [&](const auto& entry) { return entry.second == pallet.pallet_id; });
    if (!pallet.area_id.empty() && pallet.carried_by.empty()) load_at_[pallet.area_id] = pallet.pallet_id;
  });
}

void EmulatedFleet::take_orders(double now_sim) {
  order_reader_.take_data([&](model::OrderAssignment&& a) {
    const auto found = index_.find(a.robot_id);
    if (found == index_.end()) return;
    ++figures_.samples_in;
    const std::size_t i = found->second;
    Link& link = links_[i];
    emulation::EmulatedRobot& robot = robots_[i];
    const bool is_current = link.order_id == a.order_id;
    const auto seen = link.seen_updates.find(a.order_id);
    const bool duplicate = seen != link.seen_updates.end() && a.update_id <= seen->second;
    if (duplicate && !a.cancelled && !is_current) {
      // Offered again after it ended (a restarted server): say again how it ended.
      for (const auto& r : link.finished) {
        if (r.order_id == a.order_id) report_writer_.write(r);
      }
      return;
    }
    link.seen_updates[a.order_id] = std::max(a.update_id, duplicate ? seen->second : 0u);
    if (a.cancelled) {
      if (is_current && a.update_id >= link.update_id && robot.withdraw()) link.order_id = 0;
      return;
    }
    if (is_current) {
      link.update_id = a.update_id;
      report(i, "ACCEPTED", now_sim);
      if (!link.phase.empty()) report(i, link.phase, now_sim);
      return;
    }
    const auto kind = orders::parse_kind(a.kind.empty() ? "transport" : a.kind);
    const auto load = load_at_.find(a.pick_area);
    std::string why = "unknown order kind '" + a.kind + "'";
    if (kind) {
      why = robot.submit({a.order_id, *kind, a.pick_area, a.pick_pose, a.drop_area, a.drop_pose,
                          load == load_at_.end() ? -1 : load->second});
    }
    if (why.empty()) {
      link.order_id = a.order_id;
      link.update_id = a.update_id;
      link.phase.clear();
      report(i, "ACCEPTED", now_sim);
      return;
    }
    ++figures_.orders_rejected;
    log_->warn("{} rejects order {}: {}", a.robot_id, a.order_id, why);
    report_writer_.write(
        {a.order_id, a.robot_id, "REJECTED", why, a.update_id, now_sim, robot.carried_load() >= 0, -1, {}});
    ++figures_.samples_out;
  });
}

void EmulatedFleet::take_grants() {
  grant_reader_.take([&](model::TrafficGrant&& grant, const dds::SampleInfo& info) {
    if (!info.valid_data) return;
    const auto found = index_.find(grant.robot_id);
    if (found == index_.end()) return;
    ++figures_.samples_in;
    Link& link = links_[found->second];
    if (link.route_sent_wall >= 0.0 && grant.version >= link.sent_version) {
      // From the request's writing to the grant's, both stamped by this host's clock: the
      // server's answer time, whatever this process was busy with when the grant arrived.
      const double latency = static_cast<double>(info.source_timestamp_ns) * 1e-9 - link.route_sent_wall;
      grant_latency_.add(latency);
      if (latency > 2.0 * options_.traffic_period_wall_s) {
        ++figures_.routes_answered_late;
        log_->debug("route v{} of {} answered after {:.0f} ms ({})", grant.version, grant.robot_id, latency * 1e3,
                    grant.status);
      }
      link.route_sent_wall = -1.0;
    }
    progress_.note_waiting_for(grant.robot_id, grant.blocked_by);
    robots_[found->second].grant(robot::permit_of(std::move(grant)));
  });
}

void EmulatedFleet::step_all(double now_sim) {
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    emulation::EmulatedRobot& robot = robots_[i];
    robot.step(now_sim, routes_);
    for (const emulation::EmulatedEvent& e : robot.take_events()) {
      using K = emulation::EmulatedEvent::Kind;
      if (e.kind == K::kPhase) {
        links_[i].phase = e.phase;
        report(i, e.phase, now_sim);
      } else if (e.kind == K::kDone) {
        report(i, "DONE", now_sim, e.load_id, e.load_pose);
        ++figures_.orders_done;
        links_[i].order_id = 0;
        links_[i].phase.clear();
      }
    }
  }
}

void EmulatedFleet::report(std::size_t i, const std::string& status, double now_sim, int pallet_id,
                           const geometry::Pose2& pallet_pose, const std::string& reason) {
  Link& link = links_[i];
  const emulation::EmulatedRobot& robot = robots_[i];
  const int carried = robot.carried_load();
  const model::OrderReport message{link.order_id,  robot.id(), status,       reason,
                                   link.update_id, now_sim,    carried >= 0, pallet_id >= 0 ? pallet_id : carried,
                                   pallet_pose};
  report_writer_.write(message);
  ++figures_.samples_out;
  if (status == "DONE" || status == "FAILED") {
    link.finished.push_back(message);
    if (link.finished.size() > kKeptReports) {
      report_writer_.unregister(link.finished.front());
      link.finished.erase(link.finished.begin());
    }
  }
}

void EmulatedFleet::publish(std::size_t i, double now_sim) {
  const emulation::EmulatedRobot& robot = robots_[i];
  Link& link = links_[i];
  model::RobotState state;
  state.robot_id = robot.id();
  state.fleet_id = options_.fleet_id;
  state.map_id = options_.map_id;
  state.pose = robot.pose();
  state.covariance = {1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-4};  // exact, but never singular
  state.localization_score = 1.0;
  state.speed = robot.speed();
  state.task_state = robot.task_state();
  state.order_id = link.order_id;
  state.carrying_pallet = robot.carried_load() >= 0;
  state.sim_time = now_sim;
  state_writer_.write(state);
  ++figures_.samples_out;

  robot::TrafficRoute route = robot.traffic_route();
  const bool new_route = route.version != link.sent_version;
  // Off the road: the empty route goes out once, as an agent's.
  if (route.points.empty() && !new_route && link.sent_off_road) return;
  // As an agent's: the route when it changes and once a second, its progress in between.
  const double now_wall = unix_seconds();
  if (new_route || route.points != link.sent_points || !route.work_area.empty() ||
      now_wall - link.request_sent_wall >= model::kRouteRepeatWallS) {
    traffic_writer_.write({robot.id(), route.version, route.points, route.progress, route.stopped_for, now_sim,
                           route.work_area, route.arrival_area, route.keep_clear, options_.map_id});
    link.sent_points = route.points;
    link.request_sent_wall = now_wall;
  } else {
    progress_writer_.write({robot.id(), route.version, route.progress, route.stopped_for, now_sim, options_.map_id});
  }
  ++figures_.samples_out;
  link.sent_off_road = route.points.empty();
  if (new_route && !route.points.empty()) {
    link.route_sent_wall = unix_seconds();
    ++figures_.routes_sent;
  }
  link.sent_version = route.version;
  if (robot.path().size() != link.path_size) {
    path_writer_.write({robot.id(), robot.path(), now_sim});
    ++figures_.samples_out;
    link.path_size = robot.path().size();
  }
}

void EmulatedFleet::watch(double now_sim) {
  for (std::size_t i = 0; i < robots_.size(); ++i) {
    const emulation::EmulatedRobot& robot = robots_[i];
    for (const auto& c : collisions_.update(robot.id(), robot.pose(), options_.body, now_sim)) {
      log_->warn("collision at t={:.2f} s sim: {} at ({:.2f}, {:.2f}) and {} at ({:.2f}, {:.2f})", c.sim_time,
                 c.robot_a, c.pose_a.x, c.pose_a.y, c.robot_b, c.pose_b.x, c.pose_b.y);
    }
    const Link& link = links_[i];
    progress_.note_state(robot.id(), robot.task_state(), now_sim);
    const std::string task = link.order_id == 0 ? "" : std::to_string(link.order_id) + "/" + link.phase;
    if (progress_.update(robot.id(), robot.pose(), task, now_sim)) {
      const auto& d = progress_.deadlocks().back();
      log_->warn("deadlock: {} made no progress on order {} for {:.0f} s sim at ({:.2f}, {:.2f})", d.robot_id, d.task,
                 d.detected - d.since, d.pose.x, d.pose.y);
    }
  }
  figures_.max_wait_s = progress_.max_wait_s(now_sim);
}

EmulatedFleetFigures EmulatedFleet::figures() const {
  EmulatedFleetFigures f = figures_;
  f.grant_latency = grant_latency_.figures();
  f.routes_unanswered =
      std::count_if(links_.begin(), links_.end(), [](const Link& l) { return l.route_sent_wall >= 0; });
  f.collisions = collisions_.collisions().size();
  f.deadlocks = progress_.deadlocks().size();
  return f;
}

}  // namespace fleet::cli
