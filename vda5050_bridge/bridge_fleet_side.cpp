// The bridge's side towards fleet-server: each VDA 5050 vehicle speaks on DDS as an agent does.
#include <algorithm>

#include "orders/order_kind.hpp"
#include "vda5050_bridge/bridge.hpp"

namespace fleet::vda5050_bridge {

void Bridge::take_pallets() {
  pallet_reader_.take_data([&](model::PalletTruth&& pallet) {
    std::erase_if(load_at_, [&](const auto& entry) { return entry.second == pallet.pallet_id; });
    if (!pallet.area_id.empty() && pallet.carried_by.empty()) load_at_[pallet.area_id] = pallet.pallet_id;
  });
}

void Bridge::take_controls() {
  control_reader_.take_data([&](model::RobotControl&& control) {
    const auto found = by_robot_.find(control.robot_id);
    if (found == by_robot_.end()) return;
    Vehicle& v = vehicles_[found->second];
    if (control.paused == v.master->paused()) return;
    v.master->set_paused(control.paused);
    log_->info("{}: {} by the operator ({} sent)", control.robot_id, control.paused ? "paused" : "resumed",
               control.paused ? "startPause" : "stopPause");
  });
}

void Bridge::take_orders(double now_sim) {
  order_reader_.take_data([&](model::OrderAssignment&& a) {
    const auto found = by_robot_.find(a.robot_id);
    if (found == by_robot_.end()) return;
    take_order(vehicles_[found->second], std::move(a), now_sim);
  });
}

void Bridge::take_order(Vehicle& v, model::OrderAssignment&& a, double now_sim) {
  vda5050::VehicleMaster& master = *v.master;
  std::optional<orders::RunningOrder> running;
  if (v.order_id != 0) running = orders::RunningOrder{v.order_id, v.update_id};
  switch (v.intake.classify(a, running)) {
    case orders::IntakeStep::kIgnore:
      return;
    case orders::IntakeStep::kRepeatFinalReport:
      report_writer_.write(model::robot_partition(v.master->id()), *v.intake.final_report(a.order_id));
      return;
    case orders::IntakeStep::kWithdraw:
      if (master.withdraw()) {
        log_->info("{}: order {} withdrawn; cancelOrder sent, going home", master.id(), a.order_id);
        v.order_id = 0;
      }
      return;
    case orders::IntakeStep::kAcknowledgeAgain:
      v.update_id = a.update_id;
      report(v, "ACCEPTED", now_sim);
      if (!v.phase.empty()) report(v, v.phase, now_sim);
      return;
    case orders::IntakeStep::kConsider:
      break;
  }
  const auto kind = orders::parse_kind(a.kind.empty() ? "transport" : a.kind);
  std::string why = orders::AssignmentIntake::refusal_of(
      {kind ? "" : "unknown order kind '" + a.kind + "'", std::nullopt,
       v.online ? "" : "vehicle " + v.address.serial_number + " is not online", master.paused()});
  if (why.empty()) {
    const auto load = load_at_.find(a.pick_area);
    why = master.submit({a.order_id, *kind, a.pick_area, a.pick_pose, a.drop_area, a.drop_pose,
                         load == load_at_.end() ? -1 : load->second});
  }
  if (why.empty()) {
    v.order_id = a.order_id;
    v.update_id = a.update_id;
    v.phase.clear();
    report(v, "ACCEPTED", now_sim);
    return;
  }
  log_->warn("{} rejects order {}: {}", a.robot_id, a.order_id, why);
  report_writer_.write(
      model::robot_partition(master.id()),
      {a.order_id, a.robot_id, "REJECTED", why, a.update_id, now_sim, master.carried_load() >= 0, -1, {}});
}

void Bridge::take_grants() {
  grant_reader_.take([&](model::TrafficGrant&& grant, const dds::SampleInfo& info) {
    if (!info.valid_data) return;
    const auto found = by_robot_.find(grant.robot_id);
    if (found == by_robot_.end()) return;
    Vehicle& v = vehicles_[found->second];
    const bool further = grant.version != v.grant_version || grant.granted_distance > v.grant_distance + 1e-9;
    if (further && v.grant_source_wall < 0.0)
      v.grant_source_wall = static_cast<double>(info.source_timestamp_ns) * 1e-9;
    v.grant_version = grant.version;
    v.grant_distance = grant.granted_distance;
    v.master->grant(robot::permit_of(std::move(grant)));
  });
}

void Bridge::report(Vehicle& v, const std::string& status, double now_sim, int pallet_id,
                    const geometry::Pose2& pallet_pose, const std::string& reason) {
  const int carried = v.master->carried_load();
  const model::OrderReport message{v.order_id,  v.master->id(), status,       reason,
                                   v.update_id, now_sim,        carried >= 0, pallet_id >= 0 ? pallet_id : carried,
                                   pallet_pose};
  const std::string partition = model::robot_partition(v.master->id());
  report_writer_.write(partition, message);
  if (status == "DONE" || status == "FAILED") {
    if (const auto dropped = v.intake.remember_end(message)) report_writer_.open(partition).unregister(*dropped);
  }
}

void Bridge::publish(Vehicle& v, double now_sim) {
  const vda5050::VehicleMaster& master = *v.master;
  model::RobotState state;
  state.robot_id = master.id();
  state.fleet_id = v.fleet->id;
  state.map_id = options_.site->site.name;
  state.pose = master.pose();
  // The vehicle localises itself; VDA 5050 reports no covariance. A small, never singular one.
  state.covariance = {1e-4, 0, 0, 0, 1e-4, 0, 0, 0, 1e-4};
  state.localization_score = 1.0;
  state.speed = master.speed();
  state.task_state = master.task_state();
  state.detail = master.last_error();
  state.order_id = v.order_id;
  state.carrying_pallet = master.carried_load() >= 0;
  state.sim_time = now_sim;
  const std::string partition = model::robot_partition(master.id());
  state_writer_.write(partition, state);
  // The vehicle's body where it reports itself: what the simulated agents' sensors and the soak's
  // collision watch see of it. Its report is the only truth there is of a vehicle of another maker.
  truth_writer_.write(partition, {master.id(), master.pose(), v.fleet->footprint, state.carrying_pallet, now_sim});

  const robot::TrafficRoute route = master.traffic_route();
  const bool new_route = route.version != v.sent_version;
  if (!(route.points.empty() && !new_route && v.sent_off_road)) {
    traffic_writer_.write(partition,
                          {master.id(), route.version, route.points, route.progress, route.stopped_for, now_sim,
                           route.work_area, route.arrival_area, route.keep_clear, options_.site->site.name});
    v.sent_off_road = route.points.empty();
    v.sent_version = route.version;
  }
  if (master.path().size() != v.path_size || new_route) {
    path_writer_.write(partition, {master.id(), master.path(), now_sim});
    v.path_size = master.path().size();
  }
}

}  // namespace fleet::vda5050_bridge
