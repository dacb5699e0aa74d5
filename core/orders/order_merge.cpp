#include "orders/order_merge.hpp"

namespace fleet::orders {

namespace {

int progress(OrderStatus status) {
  switch (status) {
    case OrderStatus::kQueued:
      return 0;
    case OrderStatus::kAssigned:
      return 1;
    case OrderStatus::kActive:
      return 2;
    case OrderStatus::kDone:
    case OrderStatus::kFailed:
    case OrderStatus::kCancelled:
      return 3;
  }
  return 0;
}

bool same_history(const Order& a, const Order& b) {
  if (a.history.size() != b.history.size()) return false;
  for (std::size_t i = 0; i < a.history.size(); ++i) {
    const OrderEvent& x = a.history[i];
    const OrderEvent& y = b.history[i];
    if (x.status != y.status || x.sim_time != y.sim_time || x.robot_id != y.robot_id) return false;
  }
  return true;
}

}  // namespace

MergeDecision merge_handed_over(const Order* own, const Order& theirs) {
  if (own == nullptr) return {MergeChoice::kAdopt, false, "created while the servers were cut off"};
  if (same_history(*own, theirs)) return {MergeChoice::kKeepOwn, false, "the same on both servers"};
  const int mine = progress(own->status);
  const int other = progress(theirs.status);
  if (is_final(own->status) && is_final(theirs.status)) {
    const bool done_twice = own->status == OrderStatus::kDone && theirs.status == OrderStatus::kDone;
    return {MergeChoice::kKeepOwn, done_twice, "ended on both servers"};
  }
  // Given to a robot on each side, it ran (or began to) twice; the further run stands.
  const bool both_ran = (with_a_robot(own->status) || is_final(own->status)) &&
                        (with_a_robot(theirs.status) || is_final(theirs.status)) && own->robot_id != theirs.robot_id &&
                        !own->robot_id.empty() && !theirs.robot_id.empty();
  if (other > mine) return {MergeChoice::kAdopt, both_ran, "further on the server that stepped down"};
  if (other < mine) return {MergeChoice::kKeepOwn, both_ran, "further on this server"};
  if (theirs.history.size() > own->history.size()) {
    return {MergeChoice::kAdopt, both_ran, "more of its history on the server that stepped down"};
  }
  return {MergeChoice::kKeepOwn, both_ran, "as far on this server"};
}

}  // namespace fleet::orders
