#pragma once
// An order as the server publishes it (OrderInfo, latched) and back: everything an order needs
// to be rebuilt is on the wire, so a reader of OrderInfo (a standby server) holds the same order
// book as the server that wrote it, steps aside (fill_steps derives them from the site).

#include <string>

#include "model/messages.hpp"
#include "orders/order.hpp"

namespace fleet::orders {

/// The order as OrderInfo, with its history (the newest model::kMaxOrderHistory events reach the
/// wire).
model::OrderInfo info_of(const Order& order);

/// The order an OrderInfo describes, steps left empty. Throws InputError naming the order and the
/// field when a status, phase or kind is not one this server knows.
Order order_of(const model::OrderInfo& info);

}  // namespace fleet::orders
