#pragma once
// The one check of an order request, shared by fleetctl, the web API and the server itself, so
// that what one accepts the others accept too.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "orders/order_kind.hpp"

namespace fleet::config {
struct FleetConfig;
}
namespace fleet::map {
struct Site;
}

namespace fleet::orders {

inline constexpr int kMinPriority = -1000;
inline constexpr int kMaxPriority = 1000;

/// What an order request names, as the requester gave it.
struct OrderRequestFields {
  std::string kind;   ///< empty: transport
  std::string from;   ///< pick area (transport); empty for a move
  std::string to;     ///< drop area (transport); the destination of a move
  std::string robot;  ///< empty: any
  std::string fleet;  ///< empty: any
  long priority = 0;
  /// A pick list worked as a loader walk: its boxes go on transporters' pallets, with no drop place.
  bool loader = false;
};

/// The names a request may use, and what each fleet can do.
struct KnownNames {
  std::vector<std::string> areas;  ///< loading areas (load places)
  std::vector<std::string> homes;  ///< parking places, where a move may go too
  std::vector<std::string> robots;
  std::vector<std::string> fleets;
  std::map<std::string, std::string> fleet_of_robot;
  std::vector<FleetAbility> abilities;    ///< one per fleet; empty: capabilities are not checked
  std::map<std::string, double> heights;  ///< load height of a place, metres; absent: 0
  /// The actions each place offers (VDA 5050 names); a place absent here offers every action.
  std::map<std::string, std::vector<std::string>> place_actions;
};

/// The names and abilities of a configuration on a site.
KnownNames known_names(const config::FleetConfig& config, const map::Site& site);

/// What is wrong with a request: the field ("kind", "from", "to", "robot", "fleet", "priority")
/// and why, naming the value and the valid ones.
struct RequestProblem {
  std::string field;
  std::string message;
};

/// The first problem of `request`, or nothing when it may be placed. Unknown names come with the
/// valid ones (or the closest when there are many); from and to must differ; some fleet (the
/// requested one, or the requested robot's) must be able to perform every action of the order.
std::optional<RequestProblem> check_order_request(const OrderRequestFields& request, const KnownNames& known);

/// The kind of a checked request (empty is transport).
OrderKind kind_of(const OrderRequestFields& request);

/// The steps of a checked request, with the places' heights.
std::vector<OrderStep> steps_of(const OrderRequestFields& request, const KnownNames& known);

}  // namespace fleet::orders
