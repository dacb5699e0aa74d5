// The transports the packing chain owes, which the server places itself.
#include <algorithm>

#include "orders/packing_chain.hpp"
#include "orders/pick_lines.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

void FleetServer::advance_packing_chain() {
  // Only an order that changed since the chain last looked can make it owe a transport.
  if (!wire_.take_change() || !options_.site.packing) return;
  // Each transport is created before the next is looked for; a handful per cycle at most.
  for (int i = 0; i < 4; ++i) {
    auto due = orders::next_chain_transport(*options_.site.packing, site_keeper_.state().ledger, book_);
    if (!due) return;
    orders::Order draft;
    draft.request_id = "packing";
    draft.pick_area = due->pick;
    draft.drop_area = due->drop;
    draft.cause = std::move(due->cause);
    draft.caused_by = std::move(due->caused_by);
    orders::fill_steps(draft, known_names());
    const orders::Order& order = book_.create(std::move(draft), clock_.now());
    log_->info("order {} created: {} -> {}, {}", order.id, order.pick_area, order.drop_area, order.cause);
    wire_.publish(order);
  }
}

}  // namespace fleet::server
