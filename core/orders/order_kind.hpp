#pragma once
// Orders as VDA 5050 describes them: a kind, and its steps — nodes (places on the site) with the
// actions to perform there.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fleet::orders {

/// `transport`: pick a load at one place and drop it at another. `move`: go to a place and stay.
/// `pick`: take items from a rack bay and drop them at a packing place (a mobile manipulator's
/// order; placed only where a fleet performs pickItem and dropItem).
enum class OrderKind { kTransport, kMove, kPick };

std::string_view to_string(OrderKind kind);
std::optional<OrderKind> parse_kind(std::string_view text);
/// "transport, move" for messages.
std::string kind_names();

/// One node of an order: the place and the actions performed there, in order (none: drive there).
struct OrderStep {
  std::string place;
  std::vector<std::string> actions;
  /// Metres above the floor the load stands at the place (a high rack place); 0 on the floor.
  double height = 0.0;
};

/// The steps of a kind between the request's places: transport [from: pick] -> [to: drop];
/// move [to]; pick [from: pickItem] -> [to: dropItem]. Heights are the places' load heights.
std::vector<OrderStep> order_steps(OrderKind kind, const std::string& from, const std::string& to,
                                   double from_height = 0.0, double to_height = 0.0);

/// What a fleet can do, for matching orders with it.
struct FleetAbility {
  std::string fleet_id;
  std::vector<std::string> actions;
  double lift_height = 0.0;  ///< highest load it reaches, metres
  /// Places its vehicles cannot reach on the lanes they fit (traffic::places_out_of_reach).
  std::vector<std::string> out_of_reach;
};

/// Empty when `fleet` can perform every step; else the first thing it cannot do
/// ("cannot 'pick'", "lifts to 0.00 m, the load at R3 stands at 4.50 m").
std::optional<std::string> incapability(const FleetAbility& fleet, const std::vector<OrderStep>& steps);

/// Empty when some fleet of `fleets` can perform `steps`; else why none can, naming the first
/// step each fleet fails, e.g. "no fleet on the site can do it: forklifts cannot 'pickItem'".
std::optional<std::string> why_no_fleet(const std::vector<FleetAbility>& fleets, const std::vector<OrderStep>& steps);

}  // namespace fleet::orders
