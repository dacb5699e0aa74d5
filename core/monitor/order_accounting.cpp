#include "monitor/order_accounting.hpp"

#include "orders/order.hpp"

namespace fleet::monitor {

OrderTally tally_orders(const std::map<std::int64_t, model::OrderInfo>& orders, std::int64_t first_id) {
  OrderTally t;
  auto begin = orders.lower_bound(first_id);
  if (begin == orders.end()) return t;
  t.first_id = begin->first;
  t.last_id = orders.rbegin()->first;
  t.created = static_cast<long>(t.last_id - t.first_id + 1);
  for (auto it = begin; it != orders.end(); ++it) {
    const auto status = orders::parse_status(it->second.state);
    if (!status) continue;  // an unreadable state counts as lost below
    switch (*status) {
      case orders::OrderStatus::Done: ++t.done; break;
      case orders::OrderStatus::Failed: ++t.failed; break;
      case orders::OrderStatus::Cancelled: ++t.cancelled; break;
      default: ++t.open; break;
    }
  }
  t.lost = t.created - t.done - t.failed - t.cancelled - t.open;
  return t;
}

}  // namespace fleet::monitor
