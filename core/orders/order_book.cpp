#include "orders/order_book.hpp"

#include <algorithm>

namespace fleet::orders {

const Order& OrderBook::create(Order draft, double now_sim) {
  draft.id = next_id_++;
  draft.status = OrderStatus::kQueued;
  draft.phase = OrderPhase::kNone;
  draft.created_sim = draft.updated_sim = now_sim;
  draft.history = {{now_sim, OrderStatus::kQueued, OrderPhase::kNone, "", "", 0.0, 0.0}};
  unfinished_.insert(draft.id);
  return orders_[draft.id] = std::move(draft);
}

void OrderBook::restore(const Order& order) {
  orders_[order.id] = order;
  if (is_final(order.status)) {
    unfinished_.erase(order.id);
  } else {
    unfinished_.insert(order.id);
  }
  next_id_ = std::max(next_id_, order.id + 1);
}

TransitionResult OrderBook::transition(std::int64_t id, OrderStatus to, double now_sim, const std::string& reason) {
  auto it = orders_.find(id);
  if (it == orders_.end()) return TransitionResult::kUnknownOrder;
  Order& order = it->second;
  if (!is_legal_transition(order.status, to)) return TransitionResult::kIllegal;
  order.status = to;
  order.updated_sim = now_sim;
  // The reason of this state, not of an earlier one: a re-queued order that is assigned again
  // no longer says why it was re-queued (the history keeps every reason).
  order.reason = reason;
  if (to == OrderStatus::kQueued) {
    order.phase = OrderPhase::kNone;
    if (!order.robot_requested) order.robot_id.clear();
  }
  if (is_final(to)) {
    order.finished_sim = now_sim;
    unfinished_.erase(id);
  }
  order.history.push_back({now_sim, to, order.phase, order.robot_id, reason, 0.0, 0.0});
  // A done order is in no phase; the history says it ended DROPPING. FAILED and CANCELLED keep
  // the phase they stopped in, which says where.
  if (to == OrderStatus::kDone) order.phase = OrderPhase::kNone;
  return TransitionResult::kApplied;
}

TransitionResult OrderBook::assign(std::int64_t id, const std::string& robot_id, double now_sim) {
  auto it = orders_.find(id);
  if (it == orders_.end()) return TransitionResult::kUnknownOrder;
  if (it->second.status != OrderStatus::kQueued) return TransitionResult::kIllegal;
  const auto result = transition(id, OrderStatus::kAssigned, now_sim);
  it->second.robot_id = robot_id;
  it->second.history.back().robot_id = robot_id;
  it->second.assigned_sim = now_sim;
  ++it->second.update_id;
  return result;
}

TransitionResult OrderBook::set_phase(std::int64_t id, OrderPhase phase, double now_sim) {
  auto it = orders_.find(id);
  if (it == orders_.end()) return TransitionResult::kUnknownOrder;
  const auto result = transition(id, OrderStatus::kActive, now_sim);
  if (result == TransitionResult::kApplied) {
    it->second.phase = phase;
    it->second.history.back().phase = phase;
  }
  return result;
}

TransitionResult OrderBook::requeue(std::int64_t id, double now_sim, const std::string& reason) {
  auto it = orders_.find(id);
  if (it == orders_.end()) return TransitionResult::kUnknownOrder;
  if (!with_a_robot(it->second.status)) return TransitionResult::kIllegal;
  const auto result = transition(id, OrderStatus::kQueued, now_sim, reason);
  ++it->second.update_id;
  return result;
}

std::vector<const Order*> OrderBook::open_orders() const {
  std::vector<const Order*> out;
  out.reserve(unfinished_.size());
  for (const std::int64_t id : unfinished_) out.push_back(&orders_.at(id));
  return out;
}

OrderRevision revision_of(const Order& order) {
  return {order.released_stops, order.approach_stops, order.pallet, order.stand, order.drop_area};
}

bool OrderBook::revise(std::int64_t id, const OrderRevision& revision, std::vector<OrderStep> steps) {
  auto it = orders_.find(id);
  if (it == orders_.end() || !with_a_robot(it->second.status) || revision_of(it->second) == revision) return false;
  Order& order = it->second;
  order.released_stops = revision.released_stops;
  order.approach_stops = revision.approach_stops;
  order.pallet = revision.pallet;
  order.stand = revision.stand;
  order.drop_area = revision.drop_area;
  order.steps = std::move(steps);
  ++order.update_id;
  return true;
}

void OrderBook::locate_last_event(std::int64_t id, double x, double y) {
  auto it = orders_.find(id);
  if (it == orders_.end() || it->second.history.empty()) return;
  it->second.history.back().robot_x = x;
  it->second.history.back().robot_y = y;
}

const Order* OrderBook::find(std::int64_t id) const {
  auto it = orders_.find(id);
  return it == orders_.end() ? nullptr : &it->second;
}

std::vector<const Order*> OrderBook::with_status(OrderStatus status) const {
  std::vector<const Order*> out;
  for (const auto& [id, order] : orders_)
    if (order.status == status) out.push_back(&order);
  return out;
}

std::vector<const Order*> OrderBook::queue() const {
  std::vector<const Order*> out;
  for (const std::int64_t id : unfinished_) {
    const Order& order = orders_.at(id);
    if (order.status == OrderStatus::kQueued) out.push_back(&order);
  }
  std::stable_sort(out.begin(), out.end(), [](const Order* a, const Order* b) { return a->priority > b->priority; });
  return out;
}

const Order* OrderBook::open_order_of(const std::string& robot_id) const {
  for (const std::int64_t id : unfinished_) {
    const Order& order = orders_.at(id);
    if (order.status != OrderStatus::kQueued && order.robot_id == robot_id) return &order;
  }
  return nullptr;
}

}  // namespace fleet::orders
