#include "orders/order_request_check.hpp"

#include <algorithm>

#include "model/names.hpp"

namespace fleet::orders {
namespace {

bool known(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

}  // namespace

std::optional<RequestProblem> check_order_request(const OrderRequestFields& request, const KnownNames& names) {
  if (request.from.empty()) return RequestProblem{"from", "missing: the pick area, one of " + model::join(names.areas)};
  if (!known(names.areas, request.from)) {
    return RequestProblem{"from", model::unknown_name_message("loading area", request.from, names.areas)};
  }
  if (request.to.empty()) return RequestProblem{"to", "missing: the drop area, one of " + model::join(names.areas)};
  if (!known(names.areas, request.to)) {
    return RequestProblem{"to", model::unknown_name_message("loading area", request.to, names.areas)};
  }
  if (request.from == request.to) {
    return RequestProblem{"to", "pick and drop are both " + request.from + "; choose another drop area"};
  }
  if (!request.robot.empty() && !known(names.robots, request.robot)) {
    return RequestProblem{"robot", model::unknown_name_message("robot", request.robot, names.robots)};
  }
  if (!request.fleet.empty() && !known(names.fleets, request.fleet)) {
    return RequestProblem{"fleet", model::unknown_name_message("fleet", request.fleet, names.fleets)};
  }
  if (request.priority < kMinPriority || request.priority > kMaxPriority) {
    return RequestProblem{"priority", std::to_string(request.priority) + " is outside " + std::to_string(kMinPriority) +
                                          " .. " + std::to_string(kMaxPriority)};
  }
  return std::nullopt;
}

}  // namespace fleet::orders
