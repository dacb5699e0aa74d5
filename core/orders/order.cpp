#include "orders/order.hpp"

#include <array>

namespace fleet::orders {

namespace {
constexpr std::array<std::string_view, 6> kStatusNames{"QUEUED", "ASSIGNED", "ACTIVE", "DONE", "FAILED", "CANCELLED"};
constexpr std::array<std::string_view, 7> kPhaseNames{"",        "TO_PICK",  "SEARCHING", "PICKING",
                                                      "TO_DROP", "DROPPING", "MOVING"};
}  // namespace

std::string_view to_string(OrderStatus status) {
  return kStatusNames[static_cast<std::size_t>(status)];
}
std::string_view to_string(OrderPhase phase) {
  return kPhaseNames[static_cast<std::size_t>(phase)];
}

std::optional<OrderStatus> parse_status(std::string_view text) {
  for (std::size_t i = 0; i < kStatusNames.size(); ++i)
    if (kStatusNames[i] == text) return static_cast<OrderStatus>(i);
  return std::nullopt;
}

std::optional<OrderPhase> parse_phase(std::string_view text) {
  for (std::size_t i = 1; i < kPhaseNames.size(); ++i)
    if (kPhaseNames[i] == text) return static_cast<OrderPhase>(i);
  return std::nullopt;
}

std::size_t step_index(OrderPhase phase) {
  return phase == OrderPhase::kToDrop || phase == OrderPhase::kDropping ? 1 : 0;
}

bool is_final(OrderStatus status) {
  return status == OrderStatus::kDone || status == OrderStatus::kFailed || status == OrderStatus::kCancelled;
}

bool with_a_robot(OrderStatus status) {
  return status == OrderStatus::kAssigned || status == OrderStatus::kActive;
}

bool is_legal_transition(OrderStatus from, OrderStatus to) {
  using S = OrderStatus;
  switch (from) {
    case S::kQueued:
      return to == S::kAssigned || to == S::kCancelled || to == S::kFailed;
    case S::kAssigned:
      return to == S::kActive || to == S::kQueued || to == S::kDone || to == S::kFailed || to == S::kCancelled;
    case S::kActive:
      return to == S::kActive || to == S::kQueued || to == S::kDone || to == S::kFailed || to == S::kCancelled;
    case S::kDone:
    case S::kFailed:
    case S::kCancelled:
      return false;
  }
  return false;
}

}  // namespace fleet::orders
