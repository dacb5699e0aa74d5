#pragma once
// Which places a transport may use, counted with the ledger and every open order: an order picks
// a load that will be there and drops where there will be room.

#include <functional>
#include <optional>
#include <random>
#include <string>

#include "geometry/polygon.hpp"
#include "map/site.hpp"
#include "orders/area_ledger.hpp"
#include "orders/order_book.hpp"

namespace fleet::orders {

/// Loads at `place_id` once every open order is done: one standing there now, minus open orders
/// taking one away, plus open orders bringing one (1: one stands there, 0: free).
int expected_loads(const AreaLedger& ledger, const OrderBook& book, const std::string& place_id);

/// Why a transport from `pick` to `drop` cannot be ordered now, or empty. The names are checked
/// already (check_order_request); a refusal says what is true now: a load there, or an open
/// order's promise.
std::string why_not_transport(const AreaLedger& ledger, const OrderBook& book, const std::string& pick,
                              const std::string& drop);

/// Whether a robot's body (convex, in the map frame) stands on a loading area: it covers the load's
/// point, or the point `approach_distance` out from it where a vehicle stands to handle the load.
bool body_stands_on(const geometry::Polygon& body, const map::LoadingArea& area, double approach_distance);

/// Whether some robot's body stands on the place `place_id` (body_stands_on); the server answers it
/// from the robots' last poses.
using PlaceTaken = std::function<bool(const std::string& place_id)>;
/// Whether a queued order is held back from dispatch for now.
using OrderHeld = std::function<bool(const Order& order)>;

/// A queued order goes out only when its load stands at the pick place and the drop place is
/// free: one chained behind another (A->B, then B->C) waits for the first to finish. It also waits
/// while a robot's body stands on either place (`taken`): a robot that just put a load down there
/// stands on it until its way off is granted, and a robot sent in meanwhile would drive into it.
bool ready_to_dispatch(const AreaLedger& ledger, const Order& order, const PlaceTaken& taken = {});

/// Whether the automatic order source [Forklift thesis, section 3] should add a transport: more
/// robots able to carry are free than transports wait in the queue. Queued orders of other kinds
/// (pick tours) wait for other robots and hold no transport back.
bool auto_transport_wanted(const OrderBook& book, long free_transport_robots);

struct TransportChoice {
  std::string pick;
  std::string drop;
};

/// An automatic transport [Forklift thesis, section 3]: from a load standing on a place now to a
/// place free now, neither promised to an open order, so it never waits on another. Drawn at
/// random with `rng` (a few tries) among the pairs `doable` accepts (the places offer pick and drop,
/// and some fleet reaches and handles both); nothing when no pair is possible.
using TransportFilter = std::function<bool(const std::string& pick, const std::string& drop)>;
std::optional<TransportChoice> choose_auto_transport(const AreaLedger& ledger, const OrderBook& book,
                                                     std::mt19937_64& rng, const TransportFilter& doable);

}  // namespace fleet::orders
