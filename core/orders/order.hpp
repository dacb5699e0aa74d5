#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace fleet::orders {

/// Lifecycle of a transport order (openTCS-like; VDA 5050 order/state semantics).
enum class OrderStatus { kQueued, kAssigned, kActive, kDone, kFailed, kCancelled };

/// What an active order's robot is doing [Forklift thesis, section 6.4].
enum class OrderPhase { kNone, kToPick, kSearching, kPicking, kToDrop, kDropping };

std::string_view to_string(OrderStatus status);
std::string_view to_string(OrderPhase phase);
std::optional<OrderStatus> parse_status(std::string_view text);
std::optional<OrderPhase> parse_phase(std::string_view text);

bool is_final(OrderStatus status);

/// Only these transitions happen; anything else is refused and logged by the caller.
///   QUEUED   -> ASSIGNED | CANCELLED | FAILED
///   ASSIGNED -> ACTIVE | QUEUED (rejected, not acknowledged, robot lost) | DONE | FAILED | CANCELLED
///   ACTIVE   -> ACTIVE (next phase) | QUEUED (robot lost without pallet) | DONE | FAILED | CANCELLED
bool is_legal_transition(OrderStatus from, OrderStatus to);

/// One step of an order's lifecycle.
struct OrderEvent {
  double sim_time = 0.0;
  OrderStatus status = OrderStatus::kQueued;
  OrderPhase phase = OrderPhase::kNone;
  std::string robot_id;
  std::string reason;
  double robot_x = 0.0;  ///< where the robot was, when the event concerns one
  double robot_y = 0.0;
};

struct Order {
  std::int64_t id = 0;
  std::string request_id;
  std::string pick_area;
  std::string drop_area;
  std::string fleet_id;  ///< requested fleet, empty for any
  std::string robot_id;  ///< requested robot before assignment; the robot after it
  bool robot_requested = false;
  int priority = 0;  ///< higher first
  OrderStatus status = OrderStatus::kQueued;
  OrderPhase phase = OrderPhase::kNone;
  std::string reason;  ///< why FAILED or CANCELLED, or why re-queued
  std::uint32_t update_id = 0;
  double created_sim = 0.0;
  double updated_sim = 0.0;
  double assigned_sim = 0.0;
  double finished_sim = 0.0;
  std::vector<OrderEvent> history;  ///< every transition, oldest first
};

}  // namespace fleet::orders
