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

void FleetServer::advance_loader_jobs() {
  const auto actions = loader_desk_.step(
      {.book = book_, .robots = robots_.entries(), .site = options_.site, .ledger = site_keeper_.state().ledger});
  if (traffic_) traffic_->set_partners(loader_desk_.partners());
  for (const orders::LoaderAction& action : actions) {
    if (action.kind == orders::LoaderAction::Kind::kCreate) {
      orders::Order draft = action.draft;
      orders::fill_steps(draft, known_names());
      const orders::Order& order = book_.create(std::move(draft), clock_.now());
      log_->info("order {} created: {} from {} for {}", order.id, orders::to_string(order.kind), order.pick_area,
                 order.cause);
      loader_desk_.transport_created(order);
      wire_.publish(order);
      continue;
    }
    const orders::Order* before = book_.find(action.order_id);
    if (before == nullptr) continue;
    orders::Order revised = *before;
    revised.drop_area = action.revision.drop_area;
    orders::fill_steps(revised, known_names());
    if (!book_.revise(action.order_id, action.revision, std::move(revised.steps))) continue;
    const orders::Order& order = *book_.find(action.order_id);
    log_->info("order {} update {} to {}: {}", order.id, order.update_id, order.robot_id, action.why);
    wire_.publish(order);
    wire_.assign(order);
  }
}

}  // namespace fleet::server
