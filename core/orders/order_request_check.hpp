#pragma once
// The one check of an order request, shared by fleetctl, the web API and the server itself, so
// that what one accepts the others accept too.

#include <optional>
#include <string>
#include <vector>

namespace fleet::orders {

inline constexpr int kMinPriority = -1000;
inline constexpr int kMaxPriority = 1000;

/// What an order request names, as the requester gave it.
struct OrderRequestFields {
  std::string from;   ///< pick area
  std::string to;     ///< drop area
  std::string robot;  ///< empty: any
  std::string fleet;  ///< empty: any
  long priority = 0;
};

/// The names a request may use.
struct KnownNames {
  std::vector<std::string> areas;
  std::vector<std::string> robots;
  std::vector<std::string> fleets;
};

/// What is wrong with a request: the field ("from", "to", "robot", "fleet", "priority") and why,
/// naming the value and the valid ones.
struct RequestProblem {
  std::string field;
  std::string message;
};

/// The first problem of `request`, or nothing when it may be placed. Unknown names come with the
/// valid ones (or the closest when there are many); from and to must differ.
std::optional<RequestProblem> check_order_request(const OrderRequestFields& request, const KnownNames& known);

}  // namespace fleet::orders
