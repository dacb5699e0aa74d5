#include "server/order_wire.hpp"

#include "common/clock.hpp"
#include "orders/order_info.hpp"

namespace fleet::server {

OrderWire::OrderWire(dds::Participant& participant, OrderStore& store, orders::OrderBook& book,
                     const orders::RobotRoster& robots, orders::RecoveryWatch& recovery, const map::Site& site)
    : store_(store),
      book_(book),
      robots_(robots),
      recovery_(recovery),
      site_(site),
      order_writer_(participant, dds::qos::latched_state()),
      info_writer_(participant, dds::qos::latched_state()) {}

void OrderWire::publish(const orders::Order& order) {
  if (auto robot = robots_.entries().find(order.robot_id);
      robot != robots_.entries().end() && !order.history.empty() && !order.history.back().robot_id.empty()) {
    book_.locate_last_event(order.id, robot->second.last.pose.x, robot->second.last.pose.y);
  }
  // Written before anyone is told: a crash after this line loses nothing that was announced.
  store_.save(order);
  info_writer_.write(orders::info_of(order));
  changed_ = true;
  if (orders::is_final(order.status)) {
    // A finished order leaves the latched Order topic, so an agent that restarts never receives
    // it again; OrderInfo keeps the record.
    model::OrderAssignment key;
    key.order_id = order.id;
    order_writer_.unregister(key);
  }
}

void OrderWire::announce(const orders::Order& order) {
  info_writer_.write(orders::info_of(order));
}

void OrderWire::assign(const orders::Order& order) {
  model::OrderAssignment msg;
  msg.order_id = order.id;
  msg.robot_id = order.robot_id;
  msg.pick_area = order.pick_area;
  msg.drop_area = order.drop_area;
  if (const auto* pick = site_.find_area(order.pick_area)) msg.pick_pose = pick->pose;
  if (const auto* drop = site_.find_area(order.drop_area)) {
    // A move to a loading area ends where a vehicle stands to handle its load, not on the load.
    msg.drop_pose = order.kind == orders::OrderKind::kMove ? drop->approach_pose(site_.approach_distance) : drop->pose;
  }
  if (const auto* parking = site_.find_home(order.drop_area); parking && order.kind == orders::OrderKind::kMove) {
    msg.drop_pose = parking->pose;
  }
  msg.kind = std::string(orders::to_string(order.kind));
  msg.lines = order.lines;
  msg.loader = order.loader && order.kind == orders::OrderKind::kPick;
  msg.released_stops = order.released_stops;
  msg.approach_stops = order.approach_stops;
  msg.pallet = order.pallet;
  msg.stand = order.stand;
  msg.update_id = order.update_id;
  order_writer_.write(msg);
  recovery_.sent(order.id, SimClock::wall_now());
}

void OrderWire::withdraw(const orders::Order& order, const std::string& robot_id) {
  model::OrderAssignment msg;
  msg.order_id = order.id;
  msg.robot_id = robot_id;
  msg.update_id = order.update_id;
  msg.cancelled = true;
  order_writer_.write(msg);
  // An ended order must not stay on the latched topic (see publish): the robot has the
  // withdrawal once it is written, a robot that comes back later is told again on its return.
  if (orders::is_final(order.status)) order_writer_.unregister(msg);
}

bool OrderWire::take_change() {
  const bool changed = changed_;
  changed_ = false;
  return changed;
}

}  // namespace fleet::server
