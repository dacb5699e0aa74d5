#include "orders/order_request_check.hpp"

#include <algorithm>

#include "config/fleet_config.hpp"
#include "map/site.hpp"
#include "model/names.hpp"

namespace fleet::orders {
namespace {

bool known(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

double height_of(const KnownNames& names, const std::string& place) {
  const auto it = names.heights.find(place);
  return it == names.heights.end() ? 0.0 : it->second;
}

std::optional<RequestProblem> check_places(OrderKind kind, const OrderRequestFields& request, const KnownNames& names) {
  if (kind == OrderKind::kMove) {
    if (!request.from.empty()) {
      return RequestProblem{"from", "a move order has no pick area: it goes to its destination and stays there"};
    }
    std::vector<std::string> places = names.areas;
    places.insert(places.end(), names.homes.begin(), names.homes.end());
    if (request.to.empty()) return RequestProblem{"to", "missing: the destination, one of " + model::join(places)};
    if (!known(places, request.to))
      return RequestProblem{"to", model::unknown_name_message("place", request.to, places)};
    return std::nullopt;
  }
  if (request.from.empty()) return RequestProblem{"from", "missing: the pick area, one of " + model::join(names.areas)};
  if (!known(names.areas, request.from)) {
    return RequestProblem{"from", model::unknown_name_message("loading area", request.from, names.areas)};
  }
  if (request.to.empty() && kind == OrderKind::kPick && request.loader) return std::nullopt;
  if (request.to.empty()) return RequestProblem{"to", "missing: the drop area, one of " + model::join(names.areas)};
  if (!known(names.areas, request.to)) {
    return RequestProblem{"to", model::unknown_name_message("loading area", request.to, names.areas)};
  }
  if (request.from == request.to) {
    return RequestProblem{"to", "pick and drop are both " + request.from + "; choose another drop area"};
  }
  return std::nullopt;
}

/// Every step's actions must be offered by its place (a finished-goods place behind its limiter is
/// picked from, never dropped at).
std::optional<RequestProblem> check_place_actions(const OrderRequestFields& request, const KnownNames& names) {
  const auto steps = steps_of(request, names);
  for (std::size_t i = 0; i < steps.size(); ++i) {
    const auto offered = names.place_actions.find(steps[i].place);
    if (offered == names.place_actions.end()) continue;
    for (const auto& action : steps[i].actions) {
      if (std::find(offered->second.begin(), offered->second.end(), action) == offered->second.end()) {
        return RequestProblem{i == 0 && steps.size() > 1 ? "from" : "to",
                              steps[i].place + " offers " + model::join(offered->second) + ", not '" + action + "'"};
      }
    }
  }
  return std::nullopt;
}

/// Some fleet allowed by the request must be able to do every step.
std::optional<RequestProblem> check_capability(const OrderRequestFields& request, const KnownNames& names) {
  if (names.abilities.empty()) return std::nullopt;
  const auto steps = steps_of(request, names);
  std::string pinned_fleet = request.fleet;
  if (!request.robot.empty()) {
    const auto it = names.fleet_of_robot.find(request.robot);
    if (it != names.fleet_of_robot.end()) pinned_fleet = it->second;
  }
  std::vector<FleetAbility> candidates;
  for (const auto& ability : names.abilities) {
    if (pinned_fleet.empty() || ability.fleet_id == pinned_fleet) candidates.push_back(ability);
  }
  const auto why = why_no_fleet(candidates, steps);
  if (!why) return std::nullopt;
  if (!request.robot.empty())
    return RequestProblem{"robot", request.robot + " is of fleet " + pinned_fleet + ": " + *why};
  if (!request.fleet.empty()) return RequestProblem{"fleet", *why};
  return RequestProblem{"kind", "a " + std::string(to_string(kind_of(request))) + " order: " + *why};
}

}  // namespace

OrderKind kind_of(const OrderRequestFields& request) {
  return request.kind.empty() ? OrderKind::kTransport : parse_kind(request.kind).value_or(OrderKind::kTransport);
}

std::vector<OrderStep> steps_of(const OrderRequestFields& request, const KnownNames& names) {
  return order_steps(kind_of(request), request.from, request.to, height_of(names, request.from),
                     height_of(names, request.to));
}

KnownNames known_names(const config::FleetConfig& config, const map::Site& site) {
  KnownNames names;
  names.areas = site.area_ids();
  for (const auto& area : site.loading_areas) {
    names.heights[area.id] = area.height;
    names.place_actions[area.id] = area.actions;
  }
  for (const auto& home : site.homes) names.homes.push_back(home.id);
  for (const auto& [fleet, robot] : config.all_robots()) {
    names.robots.push_back(robot->id);
    names.fleet_of_robot[robot->id] = fleet->id;
  }
  for (const auto& fleet : config.fleets) {
    names.fleets.push_back(fleet.id);
    names.abilities.push_back({fleet.id, fleet.profile.actions, fleet.profile.load.lift_height, {}});
  }
  return names;
}

std::optional<RequestProblem> check_order_request(const OrderRequestFields& request, const KnownNames& names) {
  if (!request.kind.empty() && !parse_kind(request.kind)) {
    return RequestProblem{"kind", "'" + request.kind + "' is not an order kind (" + kind_names() + ")"};
  }
  if (auto problem = check_places(kind_of(request), request, names)) return problem;
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
  // What no fleet can do is named first; then what the places do not offer.
  if (auto problem = check_capability(request, names)) return problem;
  return check_place_actions(request, names);
}

}  // namespace fleet::orders
