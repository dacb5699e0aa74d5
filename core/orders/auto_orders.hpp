#pragma once
// The automatic order source [Forklift thesis, section 3]: while it is on, a few times a second,
// a random transport while robots able to carry outnumber the queued transports, and a pick list
// (cut into tours) while free pickers outnumber the queued pick orders. It drafts; the server adds,
// stores and publishes what it drafts, like any order request's.

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "orders/order.hpp"
#include "orders/order_intake.hpp"

namespace fleet::orders {

class AutoOrders {
 public:
  /// At most one round in this many wall seconds: each round looks at every robot.
  static constexpr double kPeriodWallS = 0.05;

  /// `seed` draws the places and pick lists, so that a seeded run repeats.
  /// `pick_handling`: how its pick lists travel (server.auto_pick_handling: tray, loader, auto).
  AutoOrders(bool on, std::uint64_t seed, std::string pick_handling = "tray")
      : on_(on), rng_(seed), handling_(std::move(pick_handling)) {}

  bool on() const { return on_; }
  void set_on(bool on) { on_ = on; }

  /// Whether a round is due at `now_wall` (on, and none within kPeriodWallS); if so, it starts now.
  bool due(double now_wall);

  /// A pick list for the free pickers of `view`, cut into tours (OrderIntake::pick_tours), to the
  /// site's first packing station, or as one loader walk of kLoaderWalkBoxes boxes when its
  /// handling says so; none when the site has no packing station, free pickers do not
  /// outnumber the queued pick orders, or the racks have nothing left to pick.
  std::vector<Order> pick_tours(const IntakeView& view);

  /// A transport from a load standing on a place to a free place, neither promised to an open
  /// order nor a packing station, nor kept for a loader job's pallet (IntakeView::reserved), that
  /// some fleet can do (choose_auto_transport); none while the
  /// free robots able to carry do not outnumber the queued transports.
  std::optional<Order> transport(const IntakeView& view);

 private:
  /// Free robots of `view` whose fleet can do orders of `kind`.
  static long free_for(const IntakeView& view, OrderKind kind);

  bool on_;
  std::mt19937_64 rng_;
  std::string handling_;
  double last_round_wall_ = -1e300;
};

}  // namespace fleet::orders
