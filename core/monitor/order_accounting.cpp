#include "monitor/order_accounting.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/percentile.hpp"
#include "orders/order.hpp"
#include "orders/pick_lines.hpp"
#include "orders/server_term.hpp"

namespace fleet::monitor {

OrderStats order_stats(const std::map<std::int64_t, model::OrderInfo>& orders, double now) {
  OrderStats stats;
  for (const char* state : {"QUEUED", "ASSIGNED", "ACTIVE", "DONE", "FAILED", "CANCELLED"}) stats.by_state[state] = 0;
  if (orders.empty()) return stats;
  double first = now;
  std::vector<double> durations;
  std::map<std::string, double> busy;
  for (const auto& [id, o] : orders) {
    ++stats.by_state[o.state];
    first = std::min(first, o.created_sim);
    if (o.state == "DONE") durations.push_back(o.updated_sim - o.created_sim);
    // Busy from each assignment until the next event that ends the robot's hold on the order.
    std::string robot;
    double since = 0.0;
    for (const auto& e : o.history) {
      const bool holds = e.state == "ASSIGNED" || e.state == "ACTIVE";
      if (holds && robot.empty()) {
        robot = e.robot_id;
        since = e.sim_time;
      } else if (!holds && !robot.empty()) {
        busy[robot] += e.sim_time - since;
        robot.clear();
      }
    }
    if (!robot.empty()) busy[robot] += now - since;
  }
  stats.span_s = std::max(0.0, now - first);
  if (stats.span_s > 0.0) {
    stats.done_per_hour = static_cast<double>(stats.by_state["DONE"]) * 3600.0 / stats.span_s;
    for (const auto& [robot, seconds] : busy) {
      if (!robot.empty()) stats.utilisation[robot] = std::min(1.0, seconds / stats.span_s);
    }
  }
  if (!durations.empty()) {
    double sum = 0.0;
    for (double d : durations) sum += d;
    stats.order_time_mean_s = sum / static_cast<double>(durations.size());
    stats.order_time_p95_s = common::percentile(durations, 0.95);
  }
  return stats;
}

OrderTally tally_orders(const std::map<std::int64_t, model::OrderInfo>& orders, std::int64_t first_id) {
  OrderTally t;
  auto begin = orders.lower_bound(first_id);
  if (begin == orders.end()) return t;
  t.first_id = begin->first;
  t.last_id = orders.rbegin()->first;
  // Ids run without a gap within a term's block (orders::first_order_id): a server that took
  // over hands out its block from the block's first id on.
  std::int64_t block = -1;
  std::int64_t block_first = 0;
  std::int64_t previous = 0;
  const auto close_block = [&] {
    if (block >= 0) t.created += static_cast<long>(previous - block_first + 1);
  };
  for (auto it = begin; it != orders.end(); ++it) {
    const std::int64_t id_block = (it->first - 1) / orders::kOrderIdsPerTerm;
    if (id_block != block) {
      close_block();
      block_first = block < 0 ? it->first : id_block * orders::kOrderIdsPerTerm + 1;
      block = id_block;
    }
    previous = it->first;
  }
  close_block();
  for (auto it = begin; it != orders.end(); ++it) {
    const auto status = orders::parse_status(it->second.state);
    if (!status) continue;  // an unreadable state counts as lost below
    switch (*status) {
      case orders::OrderStatus::kDone:
        ++t.done;
        break;
      case orders::OrderStatus::kFailed:
        ++t.failed;
        break;
      case orders::OrderStatus::kCancelled:
        ++t.cancelled;
        break;
      default:
        ++t.open;
        break;
    }
  }
  t.lost = t.created - t.done - t.failed - t.cancelled - t.open;
  return t;
}

std::map<std::string, long> done_by_kind(const std::map<std::int64_t, model::OrderInfo>& orders,
                                         std::int64_t first_id) {
  std::map<std::string, long> done{{"transport", 0}, {"pick", 0}, {"chained", 0}};
  for (auto it = orders.lower_bound(first_id); it != orders.end(); ++it) {
    const model::OrderInfo& o = it->second;
    if (o.state != "DONE") continue;
    if (!o.cause.empty()) {
      ++done["chained"];
    } else {
      ++done[o.kind.empty() ? std::string("transport") : o.kind];
    }
  }
  return done;
}

PickingFigures picking_figures(const std::map<std::int64_t, model::OrderInfo>& orders, std::int64_t first_id) {
  PickingFigures f;
  for (auto it = orders.lower_bound(first_id); it != orders.end(); ++it) {
    const model::OrderInfo& o = it->second;
    if (o.kind != "pick" || o.state != "DONE") continue;
    long boxes = 0;
    for (const auto& line : orders::parse_pick_lines(o.lines, "order " + std::to_string(o.order_id))) {
      boxes += line.quantity;
    }
    ++f.pick_orders_done;
    f.boxes_picked += boxes;
    if (o.loader) {
      ++f.loader_jobs_done;
      f.boxes_loaded += boxes;
    }
    f.picker_hours += std::max(0.0, o.finished_sim - o.assigned_sim) / 3600.0;
  }
  f.items_per_hour = f.picker_hours > 0.0 ? static_cast<double>(f.boxes_picked) / f.picker_hours : 0.0;
  return f;
}

}  // namespace fleet::monitor
