#pragma once

#include <optional>
#include <span>

#include "orders/order.hpp"

namespace fleet::robot {

/// What a stacker is doing [Stacker thesis, Fig. 5.6/5.7/6.7]: driving its traffic-granted route,
/// docking to a pallet in reverse, lifting it, driving on, docking the carried pallet onto its
/// drop place, lowering it, and driving home, where it parks in reverse the same way it docks.
enum class StackerState {
  kIdle,      ///< parked at home (or where a move order left it)
  kToPick,    ///< on the roads to the pick place's approach
  kDocking,   ///< the docking law, from target 1 to the forks in the pallet
  kLifting,   ///< forks rising
  kToDrop,    ///< on the roads with the pallet
  kPlacing,   ///< the docking law with the carried pallet onto the drop place
  kLowering,  ///< forks lowering, then out
  kToPlace,   ///< on the roads to a move order's place
  kToHome,    ///< on the roads home
  kParking,   ///< reversing into its stall (home or a move order's place)
  kHolding,   ///< a transport with no drop place yet: standing with its load
  kToStand,   ///< on the roads with its load to where the order has it stand
  kStanding,  ///< reversing with its load into that stand, or moving up straight back to it
};

enum class StackerEvent {
  kTransport,   ///< a transport order was accepted
  kMove,        ///< a move order was accepted
  kMoveUp,      ///< a move order whose place lies straight behind the forks, on its line: it backs there
  kRouteEnded,  ///< the route's end is reached
  kDocked,      ///< the docking law finished (forks in, pallet put, or parked)
  kDockFailed,  ///< the docking law gave up (pallet not found, forks off the pockets, timeout)
  kForksUp,     ///< the load is lifted
  kForksDown,   ///< the load is down and the forks free
  kCancel,      ///< the server withdrew the order
  kHold,        ///< the load is lifted and the order names no drop place yet
  kStand,       ///< the order has it stand elsewhere with its load: a route there
  kStandBack,   ///< the order has it stand straight behind its forks, on its line
  kDrop,        ///< the order names its drop place
};

const char* to_string(StackerState state);
const char* to_string(StackerEvent event);

struct StackerTransition {
  StackerState from;
  StackerEvent event;
  StackerState to;
};

/// Every transition the stacker's job makes; anything else is refused. A failed docking at the
/// pick place ends the order and sends the stacker home; a failed placing or parking is retried
/// from target 1 (the pallet on the forks cannot be left in the road).
std::span<const StackerTransition> stacker_transition_table();
/// The state `event` leads to from `from`, or nothing.
std::optional<StackerState> next_stacker_state(StackerState from, StackerEvent event);
/// The phase of the order a stacker in `state` is in (kNone without an order).
orders::OrderPhase stacker_phase(StackerState state);
/// Whether the stacker follows a route on the roads in `state`.
bool drives_route(StackerState state);

}  // namespace fleet::robot
