#pragma once
// What the robots and the other servers hear of the orders: OrderInfo (latched, the record a
// standby mirrors and fleetctl reads) and Order (latched, the assignment or withdrawal a robot
// acts on). An order is stored before either is written, so a crash loses nothing announced.

#include <cstdint>
#include <string>

#include "dds/topics.hpp"
#include "map/site.hpp"
#include "orders/order.hpp"
#include "orders/order_book.hpp"
#include "orders/recovery_watch.hpp"
#include "orders/robot_roster.hpp"
#include "server/order_store.hpp"

namespace fleet::server {

class OrderWire {
 public:
  /// Every reference must outlive it; `site` is read at each assignment (it changes on a map switch).
  OrderWire(dds::Participant& participant, OrderStore& store, orders::OrderBook& book,
            const orders::RobotRoster& robots, orders::RecoveryWatch& recovery, const map::Site& site);

  /// Stores the order, then publishes its record (OrderInfo); an ended order leaves the latched
  /// Order topic. Its last event is placed where its robot stands.
  void publish(const orders::Order& order);
  /// Publishes the record of an order restored from the store (already stored).
  void announce(const orders::Order& order);
  /// Sends the order to its robot (Order, with the order's update id); the recovery watch then
  /// waits for its acknowledgement.
  void assign(const orders::Order& order);
  /// Tells `robot_id` to drop `order` (VDA 5050 style: with the order's update id, so a late
  /// duplicate of an older assignment cannot undo it).
  void withdraw(const orders::Order& order, const std::string& robot_id);
  /// Whether an order was published since the last call.
  bool take_change();

 private:
  OrderStore& store_;
  orders::OrderBook& book_;
  const orders::RobotRoster& robots_;
  orders::RecoveryWatch& recovery_;
  const map::Site& site_;
  dds::Writer<model::OrderAssignment> order_writer_;
  dds::Writer<model::OrderInfo> info_writer_;
  bool changed_ = true;
};

}  // namespace fleet::server
