// The server's load truth (the area ledger) and the orders' reports that move loads.
#include <algorithm>

#include "orders/order_recovery.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderStatus;
using orders::TransitionResult;

namespace {
constexpr const char* kPallet = "pallet";  // the only kind of load this simulation moves

model::PalletTruth pallet_of(const orders::Load& load) {
  return {load.id, load.pose, load.place, load.carried_by};
}
}  // namespace

void FleetServer::restore_site_state() {
  std::vector<std::string> robots;
  for (const auto& [fleet, robot] : options_.config.all_robots()) robots.push_back(robot->id);
  const orders::SiteNames names = orders::site_names_of(options_.site, robots);
  site_ = orders::SiteState{options_.site.name, orders::AreaLedger(names.places), {}, {}};
  for (const auto& [fleet, robot] : options_.config.all_robots()) site_.parked_at[robot->id] = robot->home;
  reset_obstacles();
  const std::optional<std::string> stored = store_.load_site_state();
  if (!stored) {
    // A fresh database: the pallets of the site file, standing exactly on their areas.
    int next_id = 1;
    for (const auto& area : options_.site.loading_areas) {
      if (!area.pallet_at_start) continue;
      orders::Load load{next_id++, kPallet, area.pose, area.id, ""};
      pallet_writer_.write(pallet_of(load));
      site_.ledger.record(std::move(load));
    }
    save_site_state();  // once for all of them
    return;
  }
  orders::RestoredSiteState restored = orders::site_state_from_json(*stored, names, store_.path());
  for (const auto& dropped : restored.dropped) log_->warn("site state in {}: {}", store_.path(), dropped);
  site_.ledger = std::move(restored.state.ledger);
  for (auto& [robot, place] : restored.state.parked_at) site_.parked_at[robot] = std::move(place);
  for (const auto& [id, on] : restored.state.obstacle_enabled) site_.obstacle_enabled[id] = on;
  for (const auto& [id, load] : site_.ledger.loads()) pallet_writer_.write(pallet_of(load));
  save_site_state();  // as read against the site now, and published for a standby
  log_->info("restored the site's state from {}: {} pallets, {} obstacles on", store_.path(),
             site_.ledger.loads().size(),
             std::count_if(site_.obstacle_enabled.begin(), site_.obstacle_enabled.end(),
                           [](const auto& entry) { return entry.second; }));
}

void FleetServer::save_site_state() {
  std::string json = orders::to_json(site_);
  store_.save_site_state(json);
  site_state_writer_.write({options_.site.name, std::move(json)});
}

void FleetServer::record_load(orders::Load load) {
  const model::PalletTruth pallet = pallet_of(load);
  site_.ledger.record(std::move(load));
  save_site_state();
  pallet_writer_.write(pallet);
}

void FleetServer::handle_order_reports() {
  order_report_reader_.take([&](model::OrderReport&& report, const dds::SampleInfo& info) {
    if (!info.valid_data || !gate_.admit(order_report_reader_.handle(), info, report.robot_id, "fleet/OrderState")) {
      return;
    }
    const Order* order = book_.find(report.order_id);
    if (!order) {
      gate_.warn(info, "order", fmt::format("report on unknown order {} from {}", report.order_id, report.robot_id));
      return;
    }
    const orders::ReportFacts facts{.order_status = order->status,
                                    .order_phase = order->phase,
                                    .from_order_robot = order->robot_id == report.robot_id,
                                    .current_update = report.update_id == order->update_id,
                                    .reported = report.status,
                                    .reports_carrying = report.carrying_pallet,
                                    .reporter_registered = robots_.registered(report.robot_id)};
    switch (orders::judge_report(facts)) {
      case orders::ReportVerdict::kHandBack:
        if (hand_back(*order, report)) return;
        [[fallthrough]];
      case orders::ReportVerdict::kStale:
        // A late duplicate or a report from a robot the order was taken from (VDA 5050 style).
        log_->debug("ignoring stale report {} on order {} from {} (update {} vs {})", report.status, report.order_id,
                    report.robot_id, report.update_id, order->update_id);
        return;
      case orders::ReportVerdict::kRepeated:
        log_->debug("order {}: {} repeated by {}", order->id, report.status, report.robot_id);
        return;
      case orders::ReportVerdict::kWithdraw:
        log_->warn("order {} is {}, but {} reports {}: told it to drop the order", order->id,
                   orders::to_string(order->status), report.robot_id, report.status);
        withdraw(*order, report.robot_id);
        return;
      case orders::ReportVerdict::kApply:
        apply_report(*order, report);
        return;
    }
  });
}

void FleetServer::apply_report(const Order& order, const model::OrderReport& report) {
  const double now = clock_.now();
  const std::int64_t id = order.id;
  recovery_.settled(id);
  TransitionResult result = TransitionResult::kApplied;
  if (report.status == "ACCEPTED") {
    log_->info("order {} accepted by {}", id, report.robot_id);
    return;
  } else if (report.status == "REJECTED") {
    log_->warn("order {} rejected by {}: {}", id, report.robot_id, report.reason);
    result = book_.requeue(id, now, "rejected by " + report.robot_id + ": " + report.reason);
    // Its published state may lag its real one: do not offer it another order at once.
    dispatcher_.rejected(report.robot_id, SimClock::wall_now());
  } else if (report.status == "DONE" && order.kind == orders::OrderKind::kMove) {
    result = book_.transition(id, OrderStatus::kDone, now);
    if (result == TransitionResult::kApplied) {
      site_.parked_at[report.robot_id] = order.drop_area;
      save_site_state();
      log_->info("order {} done: {} parks at {}", id, report.robot_id, order.drop_area);
    }
  } else if (report.status == "DONE" && order.kind == orders::OrderKind::kPick) {
    // Boxes, not the pallets they stood on: the pallet ledger is unchanged.
    result = book_.transition(id, OrderStatus::kDone, now);
    if (result == TransitionResult::kApplied)
      log_->info("order {} done: {} put its boxes down at {}", id, report.robot_id, order.drop_area);
  } else if (report.status == "DONE") {
    result = book_.transition(id, OrderStatus::kDone, now);
    if (result == TransitionResult::kApplied) load_put_down(order, report);
  } else if (report.status == "FAILED") {
    result = book_.transition(id, OrderStatus::kFailed, now, report.reason);
    if (result == TransitionResult::kApplied) {
      log_->warn("order {} failed on {}: {}", id, report.robot_id, report.reason);
      if (report.reason.find("empty") != std::string::npos) pick_found_empty(order, report);
    }
  } else if (const auto phase = orders::parse_phase(report.status)) {
    if (*phase == order.phase) return;
    result = book_.set_phase(id, *phase, now);
    if (result == TransitionResult::kApplied) {
      log_->info("order {} on {}: {}", id, report.robot_id, report.status);
      // [Forklift thesis, section 8]: the server keeps the pallet map up to date as robots pick.
      if (report.carrying_pallet && orders::past_the_lift(*phase)) load_lifted(order, report);
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
}

void FleetServer::load_put_down(const Order& order, const model::OrderReport& report) {
  // The pallet stands where the robot really put it (simulation truth), so a sloppy drop makes
  // the next pick from that area harder.
  auto placed = site_.ledger.put_down(report.pallet_id, report.pallet_pose, order.drop_area);
  if (!placed) {
    log_->warn("order {} done by {} without naming the pallet it put down; pallet truth unchanged", order.id,
               report.robot_id);
    site_.ledger.record_unnamed_drop(order.drop_area);
    save_site_state();
    return;
  }
  const auto* drop = options_.site.find_area(order.drop_area);
  const double error = drop ? geometry::distance(placed->pose.position(), drop->pose.position()) : 0.0;
  record_load(std::move(*placed));
  log_->info("order {} done by {}: pallet {} placed at {} ({:.3f} m from the area's centre)", order.id, report.robot_id,
             report.pallet_id, order.drop_area, error);
}

void FleetServer::pick_found_empty(const Order& order, const model::OrderReport& report) {
  const auto* standing = site_.ledger.found_empty(order.pick_area);
  save_site_state();
  if (standing) {
    log_->warn(
        "order {}: {} found loading area {} empty, but pallet {} stands there at ({:.3f}, {:.3f}) "
        "by the record; the area stays occupied",
        order.id, report.robot_id, order.pick_area, standing->id, standing->pose.x, standing->pose.y);
  }
}

void FleetServer::load_lifted(const Order& order, const model::OrderReport& report) {
  auto lifted = site_.ledger.lifted(report.robot_id, report.pallet_id, order.pick_area);
  if (!lifted) return;
  const int load_id = lifted->id;
  record_load(std::move(*lifted));
  log_->info("pallet {} lifted by {} from {}", load_id, report.robot_id, order.pick_area);
}

void FleetServer::return_pallet_of(const std::string& robot_id, const std::string& preferred_area) {
  // A simulated robot restarts at its home with empty forks, so the pallet it carried would be
  // nowhere, and a fleet that loses one pallet per crash soon has no work. Where a real fleet's
  // operator takes the pallet off the crashed robot and puts it back, the simulation puts it on
  // the order's pick area, or the first free one.
  const orders::Load* carried = site_.ledger.carried_by(robot_id);
  if (!carried) return;
  auto back = site_.ledger.returned_from(robot_id, preferred_area);
  if (!back) {
    log_->warn("pallet {} of restarted robot {} has no free loading area to go back to", carried->id, robot_id);
    return;
  }
  log_->info("pallet {} of restarted robot {} put back on {} (simulation: the operator's part)", back->id, robot_id,
             back->place);
  record_load(std::move(*back));
}

}  // namespace fleet::server
