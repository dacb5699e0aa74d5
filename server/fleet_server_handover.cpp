// The orders a server that stepped down hands over, merged into the active server's book; and
// the ones this server hands over when it steps down itself.

#include <optional>

#include "common/errors.hpp"
#include "orders/order_merge.hpp"
#include "orders/order_recovery.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

using orders::Order;
using orders::OrderStatus;

std::vector<model::OrderInfo> FleetServer::orders_to_hand_over() const {
  // Orders a few seconds older than the silence: what was on its way when the link went.
  constexpr double kBeforeSilenceS = 5.0;
  const double active_since = static_cast<double>(term_.since_unix_ms) / 1000.0;
  const double since_wall = std::max(peers_.silence_began_wall(), active_since) - kBeforeSilenceS;
  const double since_sim = since_wall * options_.time_scale;
  std::vector<model::OrderInfo> handed;
  for (const auto& [id, order] : book_.all()) {
    if (order.updated_sim >= since_sim) handed.push_back(info_of(order));
  }
  return handed;
}

void FleetServer::handle_handed_over_orders() {
  handover_reader_.take_data([&](model::OrderHandover&& info) {
    Order theirs;
    try {
      theirs = orders::order_of(info);
    } catch (const InputError& e) {
      log_->error("order {} handed over by a server that stepped down is not taken: {}", info.order_id, e.what());
      return;
    }
    orders::fill_steps(theirs, known_names());
    const Order* own = book_.find(theirs.id);
    const orders::MergeDecision decision = orders::merge_handed_over(own, theirs);
    if (decision.ran_on_both_sides) {
      log_->error("order {} ran on both sides of a partition (robot {} here, {} on the server that stepped down): {}",
                  theirs.id, own ? own->robot_id : "", theirs.robot_id, decision.why);
    }
    if (decision.choice == orders::MergeChoice::kKeepOwn) {
      log_->debug("order {} handed over: this server's version stays ({})", theirs.id, decision.why);
      return;
    }
    // The robot this server gave it to drops it when the other side's run stands: told with the
    // version it was given (its update id), which the adopted one replaces in the book.
    std::optional<Order> withdrawn;
    if (own && orders::with_a_robot(own->status) && own->robot_id != theirs.robot_id) {
      withdrawn = *own;
    }
    const bool moved_here =
        own && (own->status == OrderStatus::kDone || orders::restored_robot_carried_load(own->phase));
    book_.restore(theirs);
    const Order& adopted = *book_.find(theirs.id);
    if (!moved_here) site_keeper_.follow(adopted, options_.site);
    if (withdrawn) wire_.withdraw(*withdrawn, withdrawn->robot_id);
    if (orders::with_a_robot(adopted.status)) {
      // As after a restart: its robot acknowledges and goes on when it is on it, refuses when it
      // is busy with another (the order goes back to the queue), and counts as lost when unheard.
      wire_.assign(adopted);
    }
    wire_.publish(adopted);
    log_->info("order {} handed over by a server that stepped down: {} {} ({})", adopted.id,
               orders::to_string(adopted.status), adopted.robot_id.empty() ? "" : "by " + adopted.robot_id,
               decision.why);
  });
}

}  // namespace fleet::server
