#include "agent/fleet_agent.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fleet::agent {

namespace {
constexpr double kServiceDistance = 0.30;  // forklift centre to pallet centre when picking, metres
constexpr double kHandlingTime = 1.0;      // sim seconds to lift or lower a pallet
constexpr double kMaxPublishHzWall = 100.0;
}  // namespace

FleetAgent::FleetAgent(AgentOptions options, Logger log)
    : options_(std::move(options)),
      log_(std::move(log)),
      clock_(options_.time_scale),
      participant_(options_.domain),
      state_writer_(participant_, dds::qos::live_state()),
      truth_writer_(participant_, dds::qos::live_state()),
      report_writer_(participant_, dds::qos::latched_state()),
      path_writer_(participant_, dds::qos::live_state()),
      order_reader_(participant_, dds::qos::latched_state()),
      map_reader_(participant_, dds::qos::latched_state()),
      obstacle_reader_(participant_, dds::qos::latched_state()),
      control_reader_(participant_, dds::qos::latched_state()),
      waitset_(participant_) {
  const auto robot = options_.config.find_robot(options_.robot_id);
  fleet_ = robot->first;
  const map::Home* home = options_.site.find_home(robot->second->home);
  home_ = home->pose;
  pose_ = home_;
  map_id_ = options_.site.name;
  for (dds_entity_t reader :
       {order_reader_.handle(), map_reader_.handle(), obstacle_reader_.handle(), control_reader_.handle()}) {
    waitset_.attach(reader);
  }
  log_->info("forklift of fleet '{}' at home {} ({:.2f}, {:.2f}, {:.2f}) on site '{}', DDS domain {}", fleet_->id,
             home->id, pose_.x, pose_.y, pose_.yaw, options_.site.name, options_.domain);
}

geometry::Pose2 FleetAgent::service_pose(const geometry::Pose2& area) const {
  // The area's yaw points from the pallet to the road: stand out along it, facing back.
  return {area.x + kServiceDistance * std::cos(area.yaw), area.y + kServiceDistance * std::sin(area.yaw),
          geometry::normalize_angle(area.yaw + std::numbers::pi)};
}

void FleetAgent::report(std::int64_t order_id, std::uint32_t update_id, const std::string& status,
                        const std::string& reason) {
  report_writer_.write(
      {order_id, options_.robot_id, status, reason, update_id, clock_.now(), carrying_pallet_, -1, {}});
}

void FleetAgent::retire_report(std::int64_t order_id) {
  // Order reports are latched so a restarted server learns how its orders ended; only the most
  // recent ones need to stay, which keeps the writer's history bounded.
  constexpr std::size_t kKeptReports = 8;
  finished_orders_.push_back(order_id);
  while (finished_orders_.size() > kKeptReports) {
    model::OrderReport key;
    key.order_id = finished_orders_.front();
    report_writer_.unregister(key);
    finished_orders_.pop_front();
  }
}

void FleetAgent::set_phase(const std::string& phase, const std::string& task_state) {
  task_state_ = task_state;
  phase_timer_ = 0.0;
  if (!order_) return;
  order_->phase = phase;
  log_->info("order {}: {} ({})", order_->assignment.order_id, phase, task_state);
  report(order_->assignment.order_id, order_->assignment.update_id, phase);
}

void FleetAgent::handle_orders() {
  order_reader_.take_data([&](model::OrderAssignment&& assignment) {
    if (assignment.robot_id != options_.robot_id) return;
    const bool is_current = order_ && order_->assignment.order_id == assignment.order_id;
    auto seen = seen_updates_.find(assignment.order_id);
    const bool duplicate = seen != seen_updates_.end() && assignment.update_id <= seen->second;
    if (duplicate && !assignment.cancelled && !is_current) return;  // a late duplicate (VDA 5050 style)
    seen_updates_[assignment.order_id] = std::max(assignment.update_id, duplicate ? seen->second : 0u);
    if (assignment.cancelled) {
      // A withdrawal older than the assignment we run is a late duplicate.
      if (is_current && assignment.update_id >= order_->assignment.update_id) {
        log_->warn("order {} withdrawn by the server; going home", assignment.order_id);
        order_.reset();
        task_state_ = "GO_HOME";
      }
      return;
    }
    if (is_current) {
      // Re-sent because our acknowledgement was lost or the server restarted: acknowledge again
      // and repeat where we are.
      order_->assignment.update_id = assignment.update_id;
      report(assignment.order_id, assignment.update_id, "ACCEPTED");
      report(assignment.order_id, assignment.update_id, order_->phase);
      return;
    }
    if (order_ || (task_state_ != "IDLE" && task_state_ != "GO_HOME")) {
      const std::string why = order_ ? "busy with order " + std::to_string(order_->assignment.order_id)
                                     : "not accepting orders in state " + task_state_;
      log_->warn("rejecting order {}: {}", assignment.order_id, why);
      report(assignment.order_id, assignment.update_id, "REJECTED", why);
      return;
    }
    log_->info("order {} accepted: {} -> {}", assignment.order_id, assignment.pick_area, assignment.drop_area);
    order_ = ActiveOrder{assignment, ""};
    report(assignment.order_id, assignment.update_id, "ACCEPTED");
    set_phase("TO_PICK", "TRACK_PATH");
  });
}

void FleetAgent::handle_site_inputs() {
  map_reader_.take_data([&](model::MapAssignment&& assignment) {
    if (assignment.robot_id != options_.robot_id) return;
    if (assignment.map_id != map_id_) log_->info("map assigned: {}", assignment.map_id);
    map_id_ = assignment.map_id;
  });
  control_reader_.take_data([&](model::RobotControl&& control) {
    if (control.robot_id != options_.robot_id || control.paused == paused_) return;
    paused_ = control.paused;
    log_->info("{} by the operator", paused_ ? "paused" : "resumed");
  });
  obstacle_reader_.take_data([&](model::StaticObstacleState&& obstacle) {
    auto it = obstacles_.find(obstacle.obstacle_id);
    if (it == obstacles_.end() || it->second != obstacle.enabled) {
      log_->info("static obstacle {} {}", obstacle.obstacle_id, obstacle.enabled ? "enabled" : "disabled");
    }
    obstacles_[obstacle.obstacle_id] = obstacle.enabled;
  });
}

bool FleetAgent::drive_towards(const geometry::Pose2& target, double dt) {
  const double v_max = options_.config.settings.get_double("agent.max_speed");
  const double w_max = options_.config.settings.get_double("agent.max_yaw_rate");
  const double tolerance = options_.config.settings.get_double("agent.goal_tolerance");
  const geometry::Vec2 to_target = target.position() - pose_.position();
  const double dist = geometry::norm(to_target);
  speed_ = 0.0;
  yaw_rate_ = 0.0;
  auto turn_to = [&](double heading) {
    const double err = geometry::angle_diff(heading, pose_.yaw);
    const double w = std::clamp(err / dt, -w_max, w_max);
    pose_.yaw = geometry::normalize_angle(pose_.yaw + w * dt);
    yaw_rate_ = w;
    return std::abs(err) < 1e-3;
  };
  if (dist > tolerance) {
    if (!turn_to(std::atan2(to_target.y, to_target.x))) return false;
    const double step = std::min(dist, v_max * dt);
    pose_.x += step * std::cos(pose_.yaw);
    pose_.y += step * std::sin(pose_.yaw);
    speed_ = step / dt;
    return false;
  }
  return turn_to(target.yaw);
}

void FleetAgent::step(double dt) {
  if (paused_) {
    speed_ = yaw_rate_ = 0.0;
    return;
  }
  phase_timer_ += dt;
  if (task_state_ == "GO_HOME") {
    if (drive_towards(home_, dt)) {
      task_state_ = "IDLE";
      log_->info("home");
    }
    return;
  }
  if (!order_) {
    speed_ = yaw_rate_ = 0.0;
    return;
  }
  const auto& a = order_->assignment;
  const std::string& phase = order_->phase;
  if (phase == "TO_PICK") {
    if (drive_towards(service_pose(a.pick_pose), dt)) set_phase("PICKING", "PICK_PALLET");
  } else if (phase == "PICKING") {
    if (phase_timer_ >= kHandlingTime) {
      carrying_pallet_ = true;
      set_phase("TO_DROP", "TRACK_PATH");
    }
  } else if (phase == "TO_DROP") {
    if (drive_towards(service_pose(a.drop_pose), dt)) set_phase("DROPPING", "DROP_PALLET");
  } else if (phase == "DROPPING") {
    if (phase_timer_ >= kHandlingTime) {
      carrying_pallet_ = false;
      log_->info("order {} done: pallet placed at {}", a.order_id, a.drop_area);
      report(a.order_id, a.update_id, "DONE");
      retire_report(a.order_id);
      order_.reset();
      task_state_ = "GO_HOME";
    }
  }
}

void FleetAgent::publish_state(double now_sim) {
  model::RobotState state;
  state.robot_id = options_.robot_id;
  state.fleet_id = fleet_->id;
  state.map_id = map_id_;
  state.pose = pose_;
  state.speed = speed_;
  state.yaw_rate = yaw_rate_;
  state.task_state = paused_ ? "PAUSED" : task_state_;
  state.order_id = order_ ? order_->assignment.order_id : 0;
  state.carrying_pallet = carrying_pallet_;
  state.sim_time = now_sim;
  state_writer_.write(state);
  truth_writer_.write({options_.robot_id, pose_, fleet_->footprint, carrying_pallet_, now_sim});
}

void FleetAgent::run(const std::atomic<bool>& stop) {
  const double sim_step = options_.config.settings.get_double("agent.sim_step_s");
  const double publish_period_wall = std::max(1.0 / kMaxPublishHzWall,
                                              clock_.to_wall(1.0 / options_.config.settings.get_double("agent.state_hz")));
  double sim_now = clock_.now();
  double last_publish_wall = 0.0;
  publish_state(sim_now);
  while (!stop.load()) {
    waitset_.wait(std::chrono::milliseconds(2));
    handle_site_inputs();
    handle_orders();
    // Advance the simulated body to the clock in fixed steps. After a long gap (the process was
    // stopped) the body does not replay the missed time: it was frozen with its software.
    const double target = clock_.now();
    if (target - sim_now > 1.0) sim_now = target - sim_step;
    while (sim_now + sim_step <= target) {
      step(sim_step);
      sim_now += sim_step;
    }
    const double now_wall = SimClock::wall_now();
    if (now_wall - last_publish_wall >= publish_period_wall) {
      publish_state(sim_now);
      last_publish_wall = now_wall;
    }
  }
  log_->info("stopping");
}

}  // namespace fleet::agent
