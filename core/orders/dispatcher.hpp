#pragma once
// Dispatch: which robots take new work now, which queued orders a round offers, and who gets
// what. The server hands over the book, the load truth and the robots as last heard, and sends
// out the assignments that come back; the decision needs no DDS, so it is tested on plain values.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "orders/area_ledger.hpp"
#include "orders/dispatch.hpp"
#include "orders/order_book.hpp"
#include "orders/robot_roster.hpp"
#include "orders/transport_areas.hpp"

namespace fleet::orders {

/// What one dispatch round reads.
struct DispatchRound {
  const OrderBook& book;
  const AreaLedger& ledger;                         ///< what stands where
  const std::map<std::string, RobotEntry>& robots;  ///< as last heard
  const std::vector<FleetAbility>& abilities;       ///< what each fleet can do
  PlaceTaken place_taken;                           ///< whether a robot's body stands on a place
  TravelCost cost;                                  ///< road metres from a robot to an order's first place
  double now_wall = 0.0;
  /// Orders the round holds back though queued (a loader walk until its first pallet stands
  /// behind its first stop: LoaderDesk::ready_for_picker); none when empty.
  OrderHeld held;
};

class Dispatcher {
 public:
  /// Robots that rejected an order are offered none for this long (wall seconds).
  static constexpr double kRejectionBackoffWallS = 2.0;

  explicit Dispatcher(std::unique_ptr<DispatchPolicy> policy) : policy_(std::move(policy)) {}

  /// `robot_id` rejected an order at `now_wall`. Its published state may lag its real one, so it
  /// is offered no other order at once.
  void rejected(const std::string& robot_id, double now_wall) { rejected_at_wall_[robot_id] = now_wall; }

  /// Whether `robot` takes new work at `now_wall`: heard and not lost, not backing off a
  /// rejection, idle or on its way home or parking there (a stacker reversing into its bay),
  /// its forks empty and no open order of its own.
  bool takes_new_work(const RobotEntry& robot, const OrderBook& book, double now_wall) const;

  /// The orders a round offers, in dispatch order: every queued order, less the transports that
  /// are not ready (ready_to_dispatch: the load at the pick, the drop free, no body on either)
  /// and the orders `held` holds back.
  static std::vector<const Order*> offered(const OrderBook& book, const AreaLedger& ledger, const PlaceTaken& taken,
                                           const OrderHeld& held = {});

  /// One round: the offered orders matched by the policy with the robots that take new work and
  /// whose fleet has an ability. Empty when nothing is offered or nobody is free.
  std::vector<Assignment> round(const DispatchRound& in) const;

 private:
  std::unique_ptr<DispatchPolicy> policy_;
  std::map<std::string, double> rejected_at_wall_;  ///< robot -> wall time of its last rejection
};

}  // namespace fleet::orders
