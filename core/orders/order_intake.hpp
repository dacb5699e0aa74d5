#pragma once
// Order intake: whether an order request is taken, and the orders it becomes. The server hands
// over what it knows at the moment of the request and adds, stores and publishes what comes back;
// the decision itself needs no DDS nor database, so it is tested here on plain values.

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "config/fleet_config.hpp"
#include "map/site.hpp"
#include "model/messages.hpp"
#include "orders/area_ledger.hpp"
#include "orders/loader_job.hpp"
#include "orders/order_book.hpp"
#include "orders/order_request_check.hpp"
#include "orders/pick_lines.hpp"

namespace fleet::orders {

/// What the intake reads of the server's state; it changes none of it.
struct IntakeView {
  const OrderBook& book;
  const AreaLedger& ledger;  ///< what stands where
  const KnownNames& names;   ///< what a request may name
  const map::Site& site;
  const std::map<std::string, std::string>& parked_at;  ///< robot -> the parking place it goes home to
  std::set<std::string> registered;                     ///< robots that reported to this server (lost ones too)
  std::set<std::string> free_robots;                    ///< registered robots that would take new work now
  bool reject_when_busy = false;                        ///< server.reject_when_busy
  double max_pickable_mass = 0.0;                       ///< max_pickable_mass of the configuration, kg
  /// The fleet that carries a loader job's pallets (loader_fleet()); empty: no pick list can be
  /// worked as a loader walk.
  std::string loader_fleet{};
  /// Boxes on one of its pallets: a loader walk's stops are cut to fit one (server.loader_pallet_boxes).
  int loader_pallet_boxes = kLoaderPalletBoxes;
  /// Road metres between two places for the picker, to order a loader walk; straight metres
  /// when null.
  PlaceDistance place_distance{};
  /// Places kept free for the pallets of loader jobs (LoaderDesk::reserved_places): random
  /// transports never go there.
  std::set<std::string> reserved{};
};

/// The fleet of `config` whose robots carry a loader job's pallets: the first of robot type
/// stacker; empty when there is none.
std::string loader_fleet(const config::FleetConfig& config);

/// The intake's answer to one request: the reply, and on acceptance the orders to add, in order.
struct IntakeDecision {
  /// Refused: the error names the field where one is at fault. Accepted: order_id is 0 until the
  /// drafts are in the book (the first one's id, set by whoever adds them); order_count is theirs.
  model::RequestReply reply;
  std::vector<Order> drafts;  ///< empty when refused
};

/// The order's VDA 5050 steps with the places' heights in `names`.
void fill_steps(Order& order, const KnownNames& names);

/// Why a command or order naming `robot_id` is refused when that robot never reported to the
/// server (`registered` does not hold it), naming those that did; nothing when it has.
std::optional<std::string> why_unseen(const std::string& robot_id, const std::set<std::string>& registered);

/// Decides order requests against one view of the server's state: each request is checked
/// whole (names, robot seen, places free, a free robot when the server rejects busy requests)
/// before anything is drafted; a pick list becomes one pick order per tour.
class OrderIntake {
 public:
  explicit OrderIntake(IntakeView view) : view_(std::move(view)) {}

  /// Takes or refuses `request`.
  IntakeDecision decide(const model::OrderRequest& request) const;
  /// Whether a checked pick list is worked as a loader walk: its request's handling, `auto`
  /// deciding by what is free; or why it cannot be.
  std::variant<bool, std::string> loader_handling(const model::OrderRequest& request) const;
  /// The list as one loader walk (docs/loader.md): one pick order, no drop place.
  Order loader_order(const std::vector<PickLine>& lines, const model::OrderRequest& request) const;
  /// Checked lines cut into tours, one pick order draft each, in the order they are to be added.
  std::vector<Order> pick_tours(const std::vector<PickLine>& lines, const model::OrderRequest& request) const;
  /// The boxes each rack place has left for new pick orders: what the site declares, less what
  /// every pick order not failed nor cancelled takes.
  std::map<std::string, map::BoxStock> boxes_left() const;
  /// Why a move to `place` by `robot_id` cannot be placed now (another registered robot parks
  /// there, or an open move goes there), or empty.
  std::string why_not_parking(const std::string& place, const std::string& robot_id) const;

 private:
  IntakeDecision decide_pick_list(const model::OrderRequest& request) const;

  /// The draft of a checked transport or move.
  Order draft_of(const model::OrderRequest& request, OrderKind kind) const;
  static IntakeDecision refuse(const model::OrderRequest& request, const std::string& error);

  IntakeView view_;
};

}  // namespace fleet::orders
