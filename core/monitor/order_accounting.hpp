#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "model/messages.hpp"

namespace fleet::monitor {

/// Order counts of a run, from the server's OrderInfo records.
struct OrderTally {
  long created = 0;  ///< every id handed out in the run: first..last within each term's block
  long done = 0;
  long failed = 0;
  long cancelled = 0;
  long open = 0;  ///< QUEUED, ASSIGNED or ACTIVE
  long lost = 0;  ///< created but neither open nor ended: an id with no record, or a record gone bad
  std::int64_t first_id = 0;
  std::int64_t last_id = 0;
};

/// What `fleetctl stats` reports.
struct OrderStats {
  std::map<std::string, long> by_state;  ///< QUEUED, ASSIGNED, ACTIVE, DONE, FAILED, CANCELLED
  double span_s = 0.0;                   ///< sim seconds from the first order's creation to now
  double done_per_hour = 0.0;            ///< per sim hour
  double order_time_mean_s = 0.0;        ///< creation to DONE, sim seconds
  double order_time_p95_s = 0.0;
  /// Per robot: the share of the span it spent on orders (assigned to ended, or to now).
  std::map<std::string, double> utilisation;
};

/// Statistics over every order known, as of sim time `now`.
OrderStats order_stats(const std::map<std::int64_t, model::OrderInfo>& orders, double now);

/// Tallies orders with ids >= `first_id` (orders of earlier runs are left out). Ids are handed out
/// increasing and never reused, without a gap within a term's block (orders::first_order_id), so
/// an id missing between the first and the last of a block, or from the start of a block after
/// the first, is an order that vanished.
OrderTally tally_orders(const std::map<std::int64_t, model::OrderInfo>& orders, std::int64_t first_id = 1);

/// Orders done, with ids >= `first_id`, by what they were: `transport` and `pick` as placed (by
/// a user or the automatic orders), and `chained`: transports the server created itself (a full
/// packing pallet to expedition, an empty one to its station; OrderInfo::cause set). Each of
/// the three is listed, 0 when none.
std::map<std::string, long> done_by_kind(const std::map<std::int64_t, model::OrderInfo>& orders,
                                         std::int64_t first_id = 1);

/// What the pickers did, over the pick orders with ids >= `first_id` that are DONE.
struct PickingFigures {
  long pick_orders_done = 0;
  long loader_jobs_done = 0;    ///< of them, walks worked as loader jobs (docs/loader.md)
  long boxes_picked = 0;        ///< boxes of the done pick orders
  long boxes_loaded = 0;        ///< of them, set on transporters' pallets by loaders
  double picker_hours = 0.0;    ///< sim hours from assignment to end of the done pick orders
  double items_per_hour = 0.0;  ///< boxes_picked / picker_hours: items an hour per working picker
};
PickingFigures picking_figures(const std::map<std::int64_t, model::OrderInfo>& orders, std::int64_t first_id = 1);

}  // namespace fleet::monitor
