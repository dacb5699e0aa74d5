#include "task/task_state_machine.hpp"

#include <array>

namespace fleet::task {

namespace {

using S = State;
using P = orders::OrderPhase;
using E = Event;
using F = Effect;

constexpr bool kAny = true;
constexpr bool kOnly = false;

// [Forklift thesis, section 6.4 and Fig. 6.9], extended with WAITING, PAUSED and ERROR.
constexpr std::array kTable = {
    // Orders: only when idle or on the way home (the thesis's IDLE_GO_HOME accepts new orders).
    TransitionRow{S::kIdle, kAny, P::kNone, E::kOrder, S::kTrackPath, P::kToPick, F::kPlanToPick},
    TransitionRow{S::kGoHome, kAny, P::kNone, E::kOrder, S::kTrackPath, P::kToPick, F::kPlanToPick},
    // Waiting for traffic on the way home is still on the way home: the server offers orders to
    // robots going home, and one that stopped for a moment would reject them.
    TransitionRow{S::kWaiting, kOnly, P::kNone, E::kOrder, S::kTrackPath, P::kToPick, F::kPlanToPick},
    // A move order: to the place, where the robot stays (it becomes its home).
    TransitionRow{S::kIdle, kAny, P::kNone, E::kMoveOrder, S::kTrackPath, P::kMoving, F::kPlanToPlace},
    TransitionRow{S::kGoHome, kAny, P::kNone, E::kMoveOrder, S::kTrackPath, P::kMoving, F::kPlanToPlace},
    TransitionRow{S::kWaiting, kOnly, P::kNone, E::kMoveOrder, S::kTrackPath, P::kMoving, F::kPlanToPlace},
    TransitionRow{S::kTrackPath, kOnly, P::kMoving, E::kPathEnded, S::kIdle, P::kNone, F::kFinishMove},
    // The order's stages.
    TransitionRow{S::kTrackPath, kOnly, P::kToPick, E::kPathEnded, S::kSearchPallet, P::kSearching, F::kStartSearch},
    TransitionRow{S::kSearchPallet, kAny, P::kNone, E::kPalletFound, S::kPickPallet, P::kPicking, F::kStartPick},
    TransitionRow{S::kSearchPallet, kAny, P::kNone, E::kAreaEmpty, S::kGoHome, P::kNone, F::kReportEmpty},
    TransitionRow{S::kPickPallet, kAny, P::kNone, E::kPickDone, S::kTrackPath, P::kToDrop, F::kPlanToDrop},
    TransitionRow{S::kPickPallet, kAny, P::kNone, E::kPickFailed, S::kSearchPallet, P::kSearching, F::kStartSearch},
    // Beyond the thesis: a robot that cannot pick stands in front of the area, usually on the road;
    // with empty forks nothing stops it from clearing the way and going home.
    TransitionRow{S::kPickPallet, kAny, P::kNone, E::kPickGaveUp, S::kGoHome, P::kNone, F::kAbandonPick},
    TransitionRow{S::kTrackPath, kOnly, P::kToDrop, E::kPathEnded, S::kDropPallet, P::kDropping, F::kStartDrop},
    TransitionRow{S::kDropPallet, kAny, P::kNone, E::kDropDone, S::kGoHome, P::kNone, F::kFinishOrder},
    TransitionRow{S::kDropPallet, kAny, P::kNone, E::kDropFailed, S::kError, P::kNone, F::kFail},
    // A pick order: beside each line's place the arm takes its boxes, then at the drop place it
    // puts them all down. The boxes on the tray are never cancelled nor left: a failed arm stops
    // the robot for an operator [Picker thesis, section 5.3.3.1.2].
    TransitionRow{S::kTrackPath, kOnly, P::kToPick, E::kAtItems, S::kPickItems, P::kPicking, F::kStartItems},
    TransitionRow{S::kPickItems, kAny, P::kNone, E::kItemsPicked, S::kTrackPath, P::kToPick, F::kPlanToPick},
    // A loader that drove ahead to a stop not yet released makes way for the transporter to come.
    TransitionRow{S::kPickItems, kAny, P::kNone, E::kStopWithdrawn, S::kTrackPath, P::kToPick, F::kPlanToPick},
    TransitionRow{S::kPickItems, kAny, P::kNone, E::kTourPicked, S::kTrackPath, P::kToDrop, F::kPlanToDrop},
    // A loader's boxes are on its transporters' pallets: the walk ends at its last place.
    TransitionRow{S::kPickItems, kAny, P::kNone, E::kWalkLoaded, S::kGoHome, P::kNone, F::kFinishOrder},
    TransitionRow{S::kTrackPath, kOnly, P::kToDrop, E::kAtItems, S::kDropItems, P::kDropping, F::kStartItems},
    TransitionRow{S::kDropItems, kAny, P::kNone, E::kItemsDropped, S::kGoHome, P::kNone, F::kFinishOrder},
    TransitionRow{S::kPickItems, kAny, P::kNone, E::kItemsFailed, S::kError, P::kNone, F::kFail},
    TransitionRow{S::kDropItems, kAny, P::kNone, E::kItemsFailed, S::kError, P::kNone, F::kFail},
    TransitionRow{S::kGoHome, kAny, P::kNone, E::kHomeReached, S::kIdle, P::kNone, F::kStop},
    // Traffic / no plan: only while driving on roads.
    TransitionRow{S::kTrackPath, kAny, P::kNone, E::kBlocked, S::kWaiting, P::kNone, F::kSuspend},
    TransitionRow{S::kGoHome, kAny, P::kNone, E::kBlocked, S::kWaiting, P::kNone, F::kSuspend},
    TransitionRow{S::kWaiting, kAny, P::kNone, E::kUnblocked, S::kWaiting, P::kNone, F::kRestore, true},
    // Operator pause: from anything but an error or an existing pause.
    TransitionRow{S::kIdle, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kTrackPath, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kSearchPallet, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kPickPallet, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kDropPallet, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kPickItems, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kDropItems, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kGoHome, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kWaiting, kAny, P::kNone, E::kPause, S::kPaused, P::kNone, F::kSuspend},
    TransitionRow{S::kPaused, kAny, P::kNone, E::kResume, S::kPaused, P::kNone, F::kRestore, true},
    // Cancel: only before the pallet is lifted; afterwards it has to be put down somewhere.
    TransitionRow{S::kTrackPath, kOnly, P::kToPick, E::kCancel, S::kGoHome, P::kNone, F::kCancelOrder},
    TransitionRow{S::kSearchPallet, kAny, P::kNone, E::kCancel, S::kGoHome, P::kNone, F::kCancelOrder},
    TransitionRow{S::kWaiting, kOnly, P::kToPick, E::kCancel, S::kGoHome, P::kNone, F::kCancelOrder},
    TransitionRow{S::kTrackPath, kOnly, P::kMoving, E::kCancel, S::kGoHome, P::kNone, F::kCancelOrder},
    TransitionRow{S::kWaiting, kOnly, P::kMoving, E::kCancel, S::kGoHome, P::kNone, F::kCancelOrder},
    // Errors.
    TransitionRow{S::kError, kAny, P::kNone, E::kReset, S::kIdle, P::kNone, F::kClear},
};

}  // namespace

std::span<const TransitionRow> transition_table() {
  return kTable;
}

const char* to_string(State s) {
  switch (s) {
    case S::kIdle:
      return "IDLE";
    case S::kTrackPath:
      return "TRACK_PATH";
    case S::kSearchPallet:
      return "SEARCH_PALLET";
    case S::kPickPallet:
      return "PICK_PALLET";
    case S::kDropPallet:
      return "DROP_PALLET";
    case S::kPickItems:
      return "PICK_ITEMS";
    case S::kDropItems:
      return "DROP_ITEMS";
    case S::kGoHome:
      return "GO_HOME";
    case S::kWaiting:
      return "WAITING";
    case S::kPaused:
      return "PAUSED";
    case S::kError:
      return "ERROR";
  }
  return "UNKNOWN";
}

const char* to_string(Event e) {
  switch (e) {
    case E::kOrder:
      return "order";
    case E::kMoveOrder:
      return "move_order";
    case E::kPathEnded:
      return "path_ended";
    case E::kPalletFound:
      return "pallet_found";
    case E::kAreaEmpty:
      return "area_empty";
    case E::kPickDone:
      return "pick_done";
    case E::kPickFailed:
      return "pick_failed";
    case E::kDropDone:
      return "drop_done";
    case E::kDropFailed:
      return "drop_failed";
    case E::kHomeReached:
      return "home_reached";
    case E::kBlocked:
      return "blocked";
    case E::kUnblocked:
      return "unblocked";
    case E::kPause:
      return "pause";
    case E::kResume:
      return "resume";
    case E::kCancel:
      return "cancel";
    case E::kPickGaveUp:
      return "pick_gave_up";
    case E::kFault:
      return "fault";
    case E::kReset:
      return "reset";
    case E::kAtItems:
      return "at_items";
    case E::kItemsPicked:
      return "items_picked";
    case E::kWalkLoaded:
      return "walk_loaded";
    case E::kTourPicked:
      return "tour_picked";
    case E::kItemsDropped:
      return "items_dropped";
    case E::kItemsFailed:
      return "items_failed";
    case E::kStopWithdrawn:
      return "stop_withdrawn";
  }
  return "unknown";
}

const char* to_string(Effect e) {
  switch (e) {
    case F::kNone:
      return "none";
    case F::kPlanToPick:
      return "plan_to_pick";
    case F::kPlanToPlace:
      return "plan_to_place";
    case F::kFinishMove:
      return "finish_move";
    case F::kStartSearch:
      return "start_search";
    case F::kStartPick:
      return "start_pick";
    case F::kPlanToDrop:
      return "plan_to_drop";
    case F::kStartDrop:
      return "start_drop";
    case F::kReportEmpty:
      return "report_empty";
    case F::kFinishOrder:
      return "finish_order";
    case F::kCancelOrder:
      return "cancel_order";
    case F::kStop:
      return "stop";
    case F::kSuspend:
      return "suspend";
    case F::kRestore:
      return "restore";
    case F::kAbandonPick:
      return "abandon_pick";
    case F::kFail:
      return "fail";
    case F::kClear:
      return "clear";
    case F::kStartItems:
      return "start_items";
  }
  return "unknown";
}

std::optional<State> TaskStateMachine::suspended_state() const {
  if (suspended_.empty()) return std::nullopt;
  return suspended_.back().state;
}

Transition TaskStateMachine::handle(Event event, const std::string& reason) {
  Transition tr;
  tr.from = state_;
  tr.from_phase = phase_;
  tr.to = state_;
  tr.to_phase = phase_;

  if (event == E::kFault) {
    if (state_ == S::kError) {
      tr.reason = "already in ERROR";
      return tr;
    }
    state_ = S::kError;
    phase_ = P::kNone;
    suspended_.clear();
    error_ = reason.empty() ? "unspecified fault" : reason;
    tr.accepted = true;
    tr.to = state_;
    tr.to_phase = phase_;
    tr.effect = F::kFail;
    tr.reason = error_;
    return tr;
  }

  for (const TransitionRow& row : kTable) {
    if (row.from != state_ || row.event != event) continue;
    if (!row.any_phase && row.phase != phase_) continue;
    tr.accepted = true;
    tr.effect = row.effect;
    tr.reason = reason;
    if (row.effect == F::kSuspend) {
      // The order phase survives the interruption: OrderState still says where the order stands.
      suspended_.push_back({state_, phase_});
      state_ = row.to;
    } else if (row.restore) {
      const Frame back = suspended_.back();
      suspended_.pop_back();
      state_ = back.state;
      phase_ = back.phase;
    } else {
      state_ = row.to;
      phase_ = row.to_phase;
      if (row.to != S::kWaiting && row.to != S::kPaused) suspended_.clear();
    }
    if (row.effect == F::kClear) error_.clear();
    if (row.effect == F::kFail) error_ = reason.empty() ? to_string(event) : reason;
    tr.to = state_;
    tr.to_phase = phase_;
    return tr;
  }
  tr.reason = std::string(to_string(event)) + " not accepted in " + to_string(state_);
  if (phase_ != P::kNone) tr.reason += " (" + std::string(orders::to_string(phase_)) + ")";
  return tr;
}

}  // namespace fleet::task
