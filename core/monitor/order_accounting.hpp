#pragma once

#include <cstdint>
#include <map>

#include "model/messages.hpp"

namespace fleet::monitor {

/// Order counts of a run, from the server's OrderInfo records.
struct OrderTally {
  long created = 0;    ///< ids first..last: every id handed out in the run
  long done = 0;
  long failed = 0;
  long cancelled = 0;
  long open = 0;       ///< QUEUED, ASSIGNED or ACTIVE
  long lost = 0;       ///< created but neither open nor ended: an id with no record, or a record gone bad
  std::int64_t first_id = 0;
  std::int64_t last_id = 0;
};

/// Tallies orders with ids >= `first_id` (orders of earlier runs are left out). Ids are handed out
/// increasing and never reused, so an id missing between the first and the last is an order that
/// vanished.
OrderTally tally_orders(const std::map<std::int64_t, model::OrderInfo>& orders, std::int64_t first_id = 1);

}  // namespace fleet::monitor
