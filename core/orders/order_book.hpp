#pragma once

#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "orders/order.hpp"

namespace fleet::orders {

/// Outcome of a requested transition.
enum class TransitionResult { kApplied, kUnknownOrder, kIllegal };

/// What a loader job may change of an order under way (orders::LoaderDesk).
struct OrderRevision {
  std::uint32_t released_stops = 0;
  std::uint32_t approach_stops = 0;
  int pallet = 0;
  std::optional<geometry::Pose2> stand{};
  std::string drop_area;
  bool operator==(const OrderRevision&) const = default;
};

/// The revision an order stands at now.
OrderRevision revision_of(const Order& order);

/// Every order the server knows, keyed by id. Ids are handed out increasing and never reused;
/// `next_id` is restored from persistence so this also holds across restarts.
class OrderBook {
 public:
  explicit OrderBook(std::int64_t next_id = 1) : next_id_(next_id) {}

  /// Creates a QUEUED order and returns it.
  const Order& create(Order draft, double now_sim);

  /// Puts back an order read from storage (its id is kept; next_id moves past it).
  void restore(const Order& order);

  /// Moves an order to `to`; refuses illegal transitions (see is_legal_transition).
  TransitionResult transition(std::int64_t id, OrderStatus to, double now_sim, const std::string& reason = "");

  /// Assigns a QUEUED order to a robot (QUEUED -> ASSIGNED) and bumps its update id.
  TransitionResult assign(std::int64_t id, const std::string& robot_id, double now_sim);

  /// Records the robot's phase of an ASSIGNED or ACTIVE order (-> ACTIVE).
  TransitionResult set_phase(std::int64_t id, OrderPhase phase, double now_sim);

  /// Sends an ASSIGNED or ACTIVE order back to the queue, with the reason.
  TransitionResult requeue(std::int64_t id, double now_sim, const std::string& reason);

  /// Tells an ASSIGNED or ACTIVE loader job order's robot something new (VDA 5050 style: an
  /// update of the same order): the fields of `revision` replace the order's, and its update id
  /// goes up; `steps` are its VDA 5050 steps with the drop place revised (fill_steps). False,
  /// with nothing changed, when they are the order's already or it has no robot.
  bool revise(std::int64_t id, const OrderRevision& revision, std::vector<OrderStep> steps);

  /// Where the robot was at the order's latest event.
  void locate_last_event(std::int64_t id, double x, double y);

  const Order* find(std::int64_t id) const;
  std::vector<const Order*> with_status(OrderStatus status) const;
  /// Queued orders by priority (high first), then age (old first).
  std::vector<const Order*> queue() const;
  /// Every order not final, by id.
  std::vector<const Order*> open_orders() const;
  /// The open (not final) order held by a robot, if any.
  const Order* open_order_of(const std::string& robot_id) const;
  const std::map<std::int64_t, Order>& all() const { return orders_; }
  std::int64_t next_id() const { return next_id_; }

 private:
  std::map<std::int64_t, Order> orders_;
  /// Ids of the orders not yet final, in id order: what the queue and a robot's open order are
  /// looked up among, while the book keeps every order of a long run.
  std::set<std::int64_t> unfinished_;
  std::int64_t next_id_;
};

}  // namespace fleet::orders
