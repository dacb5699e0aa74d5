// The robots' reports on their orders: judged against the book, then applied (the loads they move
// go to the site keeper).
#include <algorithm>

#include "orders/order_recovery.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderStatus;
using orders::TransitionResult;

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
        if (recovery_.hand_back(*order, report)) return;
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
        wire_.withdraw(*order, report.robot_id);
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
  watch_.settled(id);
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
      site_keeper_.park(report.robot_id, order.drop_area);
      log_->info("order {} done: {} parks at {}", id, report.robot_id, order.drop_area);
    }
  } else if (report.status == "DONE" && order.kind == orders::OrderKind::kPick) {
    // Boxes, not the pallets they stood on: the pallet ledger is unchanged.
    result = book_.transition(id, OrderStatus::kDone, now);
    if (result == TransitionResult::kApplied && order.loader) {
      log_->info("order {} done: {} set its last boxes on the pallet behind it", id, report.robot_id);
    } else if (result == TransitionResult::kApplied) {
      log_->info("order {} done: {} put its boxes down at {}", id, report.robot_id, order.drop_area);
    }
  } else if (report.status == "DONE") {
    result = book_.transition(id, OrderStatus::kDone, now);
    if (result == TransitionResult::kApplied) site_keeper_.put_down(order, report, options_.site);
  } else if (report.status == "FAILED") {
    result = book_.transition(id, OrderStatus::kFailed, now, report.reason);
    if (result == TransitionResult::kApplied) {
      log_->warn("order {} failed on {}: {}", id, report.robot_id, report.reason);
      if (report.reason.find("empty") != std::string::npos) site_keeper_.found_empty(order, report);
    }
  } else if (const auto phase = orders::parse_phase(report.status)) {
    if (*phase == order.phase) return;
    result = book_.set_phase(id, *phase, now);
    if (result == TransitionResult::kApplied) {
      log_->info("order {} on {}: {}", id, report.robot_id, report.status);
      // [Forklift thesis, section 8]: the server keeps the pallet map up to date as robots pick.
      if (report.carrying_pallet && orders::past_the_lift(*phase)) site_keeper_.lifted(order, report);
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
  wire_.publish(*book_.find(id));
}

}  // namespace fleet::server
