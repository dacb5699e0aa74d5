#include "orders/transport_areas.hpp"

#include <algorithm>
#include <set>
#include <vector>

namespace fleet::orders {

namespace {
template <typename UsesPlace>
const Order* open_order(const OrderBook& book, UsesPlace&& uses_place) {
  for (const auto& [id, o] : book.all()) {
    if (!is_final(o.status) && uses_place(o)) return &o;
  }
  return nullptr;
}
}  // namespace

int expected_loads(const AreaLedger& ledger, const OrderBook& book, const std::string& place_id) {
  int balance = ledger.holds_load(place_id) ? 1 : 0;
  for (const auto& [id, o] : book.all()) {
    // Pick orders move boxes and moves move robots; only transports move loads.
    if (is_final(o.status) || o.kind != OrderKind::kTransport) continue;
    if (o.pick_area == place_id) --balance;
    if (o.drop_area == place_id) ++balance;
  }
  return balance;
}

std::string why_not_transport(const AreaLedger& ledger, const OrderBook& book, const std::string& pick,
                              const std::string& drop) {
  if (expected_loads(ledger, book, pick) <= 0) {
    if (const Order* taker = open_order(book, [&](const Order& o) { return o.pick_area == pick; })) {
      return "the pallet on loading area '" + pick + "' is promised to order " + std::to_string(taker->id) +
             ", which picks it up";
    }
    return "loading area '" + pick + "' holds no pallet to pick";
  }
  if (expected_loads(ledger, book, drop) > 0) {
    if (const Order* bringer = open_order(book, [&](const Order& o) { return o.drop_area == drop; })) {
      return "loading area '" + drop + "' is promised to order " + std::to_string(bringer->id) +
             ", which drops its pallet there";
    }
    return "loading area '" + drop + "' holds a pallet";
  }
  return "";
}

bool body_stands_on(const geometry::Polygon& body, const map::LoadingArea& area, double approach_distance) {
  if (body.size() < 3) return false;
  return geometry::contains(body, area.pose.position()) ||
         geometry::contains(body, area.approach_pose(approach_distance).position());
}

bool ready_to_dispatch(const AreaLedger& ledger, const Order& order, const PlaceTaken& taken) {
  if (!ledger.holds_load(order.pick_area) || ledger.holds_load(order.drop_area)) return false;
  return !taken || (!taken(order.pick_area) && !taken(order.drop_area));
}

bool auto_transport_wanted(const OrderBook& book, long free_transport_robots) {
  const auto queued = book.with_status(OrderStatus::kQueued);
  const long queued_transports =
      std::count_if(queued.begin(), queued.end(), [](const Order* o) { return o->kind == OrderKind::kTransport; });
  return free_transport_robots > queued_transports;
}

std::optional<TransportChoice> choose_auto_transport(const AreaLedger& ledger, const OrderBook& book,
                                                     std::mt19937_64& rng, const TransportFilter& doable) {
  constexpr int kTries = 16;
  std::set<std::string> promised;
  for (const auto& [id, o] : book.all()) {
    if (is_final(o.status)) continue;
    promised.insert(o.pick_area);
    promised.insert(o.drop_area);
  }
  std::vector<std::string> picks, drops;
  for (const auto& place : ledger.places()) {
    if (promised.contains(place.id)) continue;
    (ledger.holds_load(place.id) ? picks : drops).push_back(place.id);
  }
  if (picks.empty() || drops.empty()) return std::nullopt;
  for (int attempt = 0; attempt < kTries; ++attempt) {
    const std::string& pick = picks[rng() % picks.size()];
    const std::string& drop = drops[rng() % drops.size()];
    if (why_not_transport(ledger, book, pick, drop).empty() && doable(pick, drop)) return TransportChoice{pick, drop};
  }
  return std::nullopt;
}

}  // namespace fleet::orders
