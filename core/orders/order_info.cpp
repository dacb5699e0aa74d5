#include "orders/order_info.hpp"

#include "common/errors.hpp"
#include "orders/order_kind.hpp"

namespace fleet::orders {

namespace {
template <typename T>
T known(std::optional<T> parsed, const model::OrderInfo& info, const char* field, const std::string& value) {
  if (!parsed) {
    throw InputError("OrderInfo of order " + std::to_string(info.order_id) + ": " + field + " '" + value +
                     "' is not one this server knows");
  }
  return *parsed;
}

/// OrderPhase::kNone is written as its name, which parse_phase (for robots' reports) does not take.
std::optional<OrderPhase> phase_of(const std::string& text) {
  return text == to_string(OrderPhase::kNone) ? std::optional(OrderPhase::kNone) : parse_phase(text);
}
}  // namespace

model::OrderInfo info_of(const Order& o) {
  model::OrderInfo info;
  info.order_id = o.id;
  info.request_id = o.request_id;
  info.pick_area = o.pick_area;
  info.drop_area = o.drop_area;
  info.fleet_id = o.fleet_id;
  info.robot_id = o.robot_id;
  info.state = std::string(to_string(o.status));
  info.phase = std::string(to_string(o.phase));
  info.reason = o.reason;
  info.priority = o.priority;
  info.created_sim = o.created_sim;
  info.updated_sim = o.updated_sim;
  for (const auto& e : o.history) {
    info.history.push_back({e.sim_time, std::string(to_string(e.status)), std::string(to_string(e.phase)), e.robot_id,
                            e.reason, e.robot_x, e.robot_y});
  }
  info.kind = std::string(to_string(o.kind));
  info.cause = o.cause;
  info.caused_by = o.caused_by;
  info.lines = o.lines;
  info.loader = o.loader;
  info.robot_requested = o.robot_requested;
  info.update_id = o.update_id;
  info.assigned_sim = o.assigned_sim;
  info.finished_sim = o.finished_sim;
  return info;
}

Order order_of(const model::OrderInfo& info) {
  Order o;
  o.id = info.order_id;
  o.request_id = info.request_id;
  o.kind = known(parse_kind(info.kind), info, "kind", info.kind);
  o.pick_area = info.pick_area;
  o.drop_area = info.drop_area;
  o.lines = info.lines;
  o.loader = info.loader;
  o.fleet_id = info.fleet_id;
  o.robot_id = info.robot_id;
  o.robot_requested = info.robot_requested;
  o.priority = info.priority;
  o.status = known(parse_status(info.state), info, "state", info.state);
  o.phase = known(phase_of(info.phase), info, "phase", info.phase);
  o.reason = info.reason;
  o.update_id = info.update_id;
  o.created_sim = info.created_sim;
  o.updated_sim = info.updated_sim;
  o.assigned_sim = info.assigned_sim;
  o.finished_sim = info.finished_sim;
  for (const auto& e : info.history) {
    o.history.push_back({e.sim_time, known(parse_status(e.state), info, "history state", e.state),
                         known(phase_of(e.phase), info, "history phase", e.phase), e.robot_id, e.reason, e.robot_x,
                         e.robot_y});
  }
  o.cause = info.cause;
  o.caused_by = info.caused_by;
  return o;
}

}  // namespace fleet::orders
