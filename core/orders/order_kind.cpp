#include "orders/order_kind.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

namespace fleet::orders {

namespace {
constexpr std::array<std::string_view, 3> kKindNames{"transport", "move", "pick"};

std::string metres(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f m", value);
  return text;
}
}  // namespace

std::string_view to_string(OrderKind kind) {
  return kKindNames[static_cast<std::size_t>(kind)];
}

std::optional<OrderKind> parse_kind(std::string_view text) {
  for (std::size_t i = 0; i < kKindNames.size(); ++i) {
    if (kKindNames[i] == text) return static_cast<OrderKind>(i);
  }
  return std::nullopt;
}

std::string kind_names() {
  std::string out;
  for (auto name : kKindNames) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

std::vector<OrderStep> order_steps(OrderKind kind, const std::string& from, const std::string& to, double from_height,
                                   double to_height) {
  switch (kind) {
    case OrderKind::kTransport:
      return {{from, {"pick"}, from_height}, {to, {"drop"}, to_height}};
    case OrderKind::kMove:
      return {{to, {}, 0.0}};
    case OrderKind::kPick:
      return {{from, {"pickItem"}, from_height}, {to, {"dropItem"}, to_height}};
  }
  return {};
}

std::optional<std::string> incapability(const FleetAbility& fleet, const std::vector<OrderStep>& steps) {
  for (const OrderStep& step : steps) {
    if (std::find(fleet.out_of_reach.begin(), fleet.out_of_reach.end(), step.place) != fleet.out_of_reach.end()) {
      return "does not reach " + step.place + " on the lanes its vehicles fit";
    }
    for (const std::string& action : step.actions) {
      if (std::find(fleet.actions.begin(), fleet.actions.end(), action) == fleet.actions.end()) {
        return "cannot '" + action + "'";
      }
    }
    if (!step.actions.empty() && step.height > fleet.lift_height + 1e-9) {
      return "lifts to " + metres(fleet.lift_height) + ", the load at " + step.place + " stands at " +
             metres(step.height);
    }
  }
  return std::nullopt;
}

std::optional<std::string> why_no_fleet(const std::vector<FleetAbility>& fleets, const std::vector<OrderStep>& steps) {
  std::string reasons;
  for (const FleetAbility& fleet : fleets) {
    const auto why = incapability(fleet, steps);
    if (!why) return std::nullopt;
    reasons += (reasons.empty() ? "" : "; ") + fleet.fleet_id + " " + *why;
  }
  return "no fleet on the site can do it: " + (reasons.empty() ? std::string("there is no fleet") : reasons);
}

}  // namespace fleet::orders
