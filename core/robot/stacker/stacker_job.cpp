#include "robot/stacker/stacker_job.hpp"

#include <array>

#include "task/transition_table.hpp"

namespace fleet::robot {

namespace {

using S = StackerState;
using E = StackerEvent;

constexpr std::array kTable{
    StackerTransition{S::kIdle, E::kTransport, S::kToPick},
    StackerTransition{S::kIdle, E::kMove, S::kToPlace},
    StackerTransition{S::kIdle, E::kMoveUp, S::kParking},
    StackerTransition{S::kToHome, E::kTransport, S::kToPick},
    StackerTransition{S::kToHome, E::kMove, S::kToPlace},
    StackerTransition{S::kParking, E::kTransport, S::kToPick},
    StackerTransition{S::kParking, E::kMove, S::kToPlace},
    StackerTransition{S::kToPick, E::kRouteEnded, S::kDocking},
    StackerTransition{S::kToPick, E::kCancel, S::kToHome},
    StackerTransition{S::kDocking, E::kDocked, S::kLifting},
    StackerTransition{S::kDocking, E::kDockFailed, S::kToHome},
    StackerTransition{S::kDocking, E::kCancel, S::kToHome},
    StackerTransition{S::kLifting, E::kForksUp, S::kToDrop},
    StackerTransition{S::kToDrop, E::kRouteEnded, S::kPlacing},
    StackerTransition{S::kPlacing, E::kDocked, S::kLowering},
    StackerTransition{S::kPlacing, E::kDockFailed, S::kPlacing},
    StackerTransition{S::kLowering, E::kForksDown, S::kToHome},
    StackerTransition{S::kToPlace, E::kRouteEnded, S::kParking},
    StackerTransition{S::kToPlace, E::kCancel, S::kToHome},
    StackerTransition{S::kToHome, E::kRouteEnded, S::kParking},
    StackerTransition{S::kParking, E::kDocked, S::kIdle},
    StackerTransition{S::kParking, E::kDockFailed, S::kParking},
    StackerTransition{S::kParking, E::kCancel, S::kToHome},
    // A transport whose drop place comes later (a loader's transporter): it stands with its load
    // where the order says until the order names the drop place.
    StackerTransition{S::kLifting, E::kHold, S::kHolding},
    StackerTransition{S::kHolding, E::kStand, S::kToStand},
    StackerTransition{S::kHolding, E::kStandBack, S::kStanding},
    StackerTransition{S::kHolding, E::kDrop, S::kToDrop},
    StackerTransition{S::kToStand, E::kRouteEnded, S::kStanding},
    StackerTransition{S::kStanding, E::kDocked, S::kHolding},
};

}  // namespace

const char* to_string(StackerState state) {
  switch (state) {
    case S::kIdle:
      return "IDLE";
    case S::kToPick:
      return "TO_PICK";
    case S::kDocking:
      return "DOCKING";
    case S::kLifting:
      return "LIFTING";
    case S::kToDrop:
      return "TO_DROP";
    case S::kPlacing:
      return "PLACING";
    case S::kLowering:
      return "LOWERING";
    case S::kToPlace:
      return "TO_PLACE";
    case S::kToHome:
      return "GO_HOME";
    case S::kParking:
      return "PARKING";
    case S::kHolding:
      return "HOLDING";
    case S::kToStand:
      return "TO_STAND";
    case S::kStanding:
      return "STANDING";
  }
  return "?";
}

const char* to_string(StackerEvent event) {
  switch (event) {
    case E::kTransport:
      return "transport";
    case E::kMoveUp:
      return "MOVE_UP";
    case E::kMove:
      return "move";
    case E::kRouteEnded:
      return "route ended";
    case E::kDocked:
      return "docked";
    case E::kDockFailed:
      return "dock failed";
    case E::kForksUp:
      return "forks up";
    case E::kForksDown:
      return "forks down";
    case E::kCancel:
      return "cancel";
    case E::kHold:
      return "hold";
    case E::kStand:
      return "stand";
    case E::kStandBack:
      return "stand back";
    case E::kDrop:
      return "drop";
  }
  return "?";
}

std::span<const StackerTransition> stacker_transition_table() {
  return kTable;
}

std::optional<StackerState> next_stacker_state(StackerState from, StackerEvent event) {
  return task::next_state(kTable, from, event);
}

orders::OrderPhase stacker_phase(StackerState state) {
  switch (state) {
    case S::kToPick:
      return orders::OrderPhase::kToPick;
    case S::kDocking:
    case S::kLifting:
      return orders::OrderPhase::kPicking;
    case S::kToDrop:
    case S::kHolding:
    case S::kToStand:
    case S::kStanding:
      return orders::OrderPhase::kToDrop;
    case S::kPlacing:
    case S::kLowering:
      return orders::OrderPhase::kDropping;
    case S::kToPlace:
      return orders::OrderPhase::kMoving;
    case S::kIdle:
    case S::kToHome:
    case S::kParking:
      return orders::OrderPhase::kNone;
  }
  return orders::OrderPhase::kNone;
}

bool drives_route(StackerState state) {
  return state == S::kToPick || state == S::kToDrop || state == S::kToPlace || state == S::kToHome ||
         state == S::kToStand;
}

}  // namespace fleet::robot
