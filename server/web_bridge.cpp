#include "server/web_bridge.hpp"

#include "common/percentile.hpp"
#include "orders/order_info.hpp"

namespace fleet::server {

void fill_orders(const std::map<std::int64_t, orders::Order>& orders, LiveSnapshot& snapshot) {
  constexpr std::size_t kRecentEndedOrders = 50;
  std::vector<const orders::Order*> ended;
  std::vector<double> durations;
  for (const auto& [id, order] : orders) {
    if (!orders::is_final(order.status)) {
      snapshot.orders.push_back(orders::info_of(order));
    } else {
      ended.push_back(&order);
    }
    if (order.status == orders::OrderStatus::kDone) {
      ++snapshot.orders_done;
      durations.push_back(order.finished_sim - order.created_sim);
    }
    if (order.status == orders::OrderStatus::kFailed) ++snapshot.orders_failed;
  }
  for (std::size_t i = ended.size() > kRecentEndedOrders ? ended.size() - kRecentEndedOrders : 0; i < ended.size();
       ++i) {
    snapshot.orders.push_back(orders::info_of(*ended[i]));
  }
  snapshot.order_time_p95_s = common::percentile(std::move(durations), 0.95);
}

}  // namespace fleet::server
