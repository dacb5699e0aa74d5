#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/pose.hpp"
#include "orders/order_kind.hpp"

namespace fleet::orders {

/// Lifecycle of a transport order (openTCS-like; VDA 5050 order/state semantics).
enum class OrderStatus { kQueued, kAssigned, kActive, kDone, kFailed, kCancelled };

/// What an active order's robot is doing: the step it executes and the action in it
/// [Forklift thesis, section 6.4]. A transport's first step is TO_PICK (driving there), SEARCHING
/// (finePositioning) and PICKING (pick); its second TO_DROP and DROPPING (drop). A move's one step
/// is MOVING.
enum class OrderPhase { kNone, kToPick, kSearching, kPicking, kToDrop, kDropping, kMoving };

/// The index in the order's steps of the step `phase` belongs to (0 for kNone).
std::size_t step_index(OrderPhase phase);

std::string_view to_string(OrderStatus status);
std::string_view to_string(OrderPhase phase);
std::optional<OrderStatus> parse_status(std::string_view text);
std::optional<OrderPhase> parse_phase(std::string_view text);

bool is_final(OrderStatus status);
/// ASSIGNED or ACTIVE: a robot has the order.
bool with_a_robot(OrderStatus status);

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
  OrderKind kind = OrderKind::kTransport;
  std::string pick_area;  ///< where a transport picks its load; empty for a move
  std::string drop_area;  ///< where a transport drops its load; where a move goes
  /// The VDA 5050 nodes with their actions, from kind and places (order_steps); filled by whoever
  /// creates or loads the order, since place heights come from the site.
  std::vector<OrderStep> steps;
  /// A pick order's tour: its lines as CSV (place,item,quantity per line, in driving order, as
  /// parse_pick_lines reads them); empty for other kinds.
  std::string lines;
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
  /// Why the server created this order itself (the packing chain), for people; empty otherwise.
  std::string cause;
  /// The orders this one follows from: the pick orders that filled the pallet it takes away, or
  /// the transport that took away the pallet it replaces.
  std::vector<std::int64_t> caused_by;

  // A loader job (docs/loader.md): its pick order and the transports that carry its pallets, and
  // what the job tells their robots beyond the places (orders::LoaderDesk revises them).
  /// A pick order worked as a loader walk, or a transport carrying a loader job's pallet.
  bool loader = false;
  std::uint32_t released_stops = 0;  ///< loader pick: the arm works the first released_stops stops
  /// loader pick: the picker may drive to the first approach_stops stops (it loads only the released)
  std::uint32_t approach_stops = 0;
  int pallet = 0;  ///< loader pick: whose pallet stands behind the picker (a transport's id)
  /// Loader transport with no drop area yet: where its robot stands with the pallet (its centre).
  std::optional<geometry::Pose2> stand{};

  /// The place the robot drives to first: the pick area, or a move's destination.
  const std::string& first_place() const { return kind == OrderKind::kMove ? drop_area : pick_area; }
};

}  // namespace fleet::orders
