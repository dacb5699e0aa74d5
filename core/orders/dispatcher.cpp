#include "orders/dispatcher.hpp"

#include <algorithm>

namespace fleet::orders {

bool Dispatcher::takes_new_work(const RobotEntry& robot, const OrderBook& book, double now_wall) const {
  if (!robot.registered || robot.lost) return false;
  if (const auto r = rejected_at_wall_.find(robot.id);
      r != rejected_at_wall_.end() && now_wall - r->second < kRejectionBackoffWallS) {
    return false;
  }
  const auto& state = robot.last.task_state;
  if (state != "IDLE" && state != "GO_HOME" && state != "PARKING") return false;
  if (robot.last.carrying_pallet) return false;
  return book.open_order_of(robot.id) == nullptr;
}

std::vector<const Order*> Dispatcher::offered(const OrderBook& book, const AreaLedger& ledger, const PlaceTaken& taken,
                                              const OrderHeld& held) {
  std::vector<const Order*> queue;
  for (const Order* o : book.queue()) {
    if (held && held(*o)) continue;
    if (o->kind != OrderKind::kTransport || ready_to_dispatch(ledger, *o, taken)) queue.push_back(o);
  }
  return queue;
}

std::vector<Assignment> Dispatcher::round(const DispatchRound& in) const {
  const auto queue = offered(in.book, in.ledger, in.place_taken, in.held);
  if (queue.empty()) return {};
  std::vector<FreeRobot> free;
  for (const auto& [id, robot] : in.robots) {
    if (!takes_new_work(robot, in.book, in.now_wall)) continue;
    if (const FleetAbility* ability = ability_of(in.abilities, robot.fleet_id)) {
      free.emplace_back(robot.id, robot.fleet_id, *ability);
    }
  }
  if (free.empty()) return {};
  return policy_->assign(queue, std::move(free), in.cost);
}

}  // namespace fleet::orders
