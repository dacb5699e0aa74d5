// The pick orders and transports the server places itself: automatic pick lists for free pickers
// (checked and cut into tours by orders::OrderIntake), and what the packing chain owes.
#include <algorithm>

#include "orders/packing_chain.hpp"
#include "orders/pick_lines.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

void FleetServer::create_auto_pick(long free_pickers) {
  // The pick lists a warehouse system would send, one tour per free picker: boxes from the racks to
  // the packing stations, whose full pallets then go on to expedition by the packing chain.
  if (!options_.site.packing || options_.site.packing->stations.empty()) return;
  const auto queue = book_.with_status(orders::OrderStatus::kQueued);
  const long queued = std::count_if(queue.begin(), queue.end(),
                                    [](const orders::Order* o) { return o->kind == orders::OrderKind::kPick; });
  if (free_pickers <= queued) return;
  const orders::OrderIntake intake(intake_view());
  const auto lines =
      orders::choose_auto_pick_list(intake.boxes_left(), orders::place_poses(options_.site),
                                    orders::max_pickable_mass(options_.config), orders::kTourBoxes, rng_);
  if (!lines) return;
  model::OrderRequest request;
  request.request_id = "auto";
  request.kind = "pick";
  request.drop_area = options_.site.packing->stations.front();
  add_orders(intake.pick_tours(*lines, request));
}

void FleetServer::advance_packing_chain() {
  if (!options_.site.packing || !chain_stale_) return;
  chain_stale_ = false;
  // Each transport is created before the next is looked for; a handful per cycle at most.
  for (int i = 0; i < 4; ++i) {
    auto due = orders::next_chain_transport(*options_.site.packing, ledger_, book_);
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
    publish_order(order);
  }
}

}  // namespace fleet::server
