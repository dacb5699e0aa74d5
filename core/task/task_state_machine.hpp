#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "orders/order.hpp"

namespace fleet::task {

/// The agent's task states [Forklift thesis, section 6.4, Fig. 6.9], plus WAITING (blocked by traffic or
/// no plan), PAUSED (on command) and ERROR (with a reason). The seed's IDLE_GO_HOME is kGoHome:
/// it drives home like TRACK_PATH but, unlike it, accepts new orders.
/// A pick order (a mobile manipulator's) has PICK_ITEMS and DROP_ITEMS in place of the pallet's
/// search, pick and drop: the arm works while the base stands beside the place.
enum class State {
  kIdle,
  kTrackPath,
  kSearchPallet,
  kPickPallet,
  kDropPallet,
  kPickItems,
  kDropItems,
  kGoHome,
  kWaiting,
  kPaused,
  kError
};

/// Inputs that can move the machine. The agent (or the TaskExecutor on its behalf) raises them.
enum class Event {
  kOrder,          ///< a transport order arrived
  kMoveOrder,      ///< a move order arrived: drive to a parking place and stay there
  kPathEnded,      ///< the follower reached the end of the planner's path
  kPalletFound,    ///< the search confirmed the marker
  kAreaEmpty,      ///< the search swept without seeing the marker
  kPickDone,       ///< pallet on the forks and lifted
  kPickFailed,     ///< marker lost or pick timed out; the search runs again
  kPickGaveUp,     ///< the pick failed too often; the forks are empty, so the order fails and it goes home
  kDropDone,       ///< pallet lowered on the target area and the forklift backed out
  kDropFailed,     ///< placement did not converge
  kHomeReached,    ///< the follower reached the home pose
  kBlocked,        ///< traffic or no plan: stand still
  kUnblocked,      ///< go on with what was interrupted
  kPause,          ///< operator pause
  kResume,         ///< operator resume
  kCancel,         ///< operator cancels the order (only before the pallet is lifted)
  kFault,          ///< something failed beyond recovery; carries a reason
  kReset,          ///< operator clears an error
  kAtItems,        ///< a pick order's path ended beside the place of its line, or of its drop
  kItemsPicked,    ///< the arm took the line's boxes; lines are left
  kTourPicked,     ///< the arm took the last line's boxes
  kWalkLoaded,     ///< a loader's arm set the walk's last boxes on the transporter behind it: no station
  kItemsDropped,   ///< the arm put every box down on the drop place
  kItemsFailed,    ///< the arm could not pick or drop (no box found, out of reach); carries a reason
  kStopWithdrawn,  ///< a loader at a stop not released may no longer wait there: its transporter changed
};

/// What the owner must do when a transition fires. One per row, so a test can check it.
enum class Effect {
  kNone,
  kPlanToPick,   ///< accept the order, request a plan to the pick area, follow it
  kPlanToPlace,  ///< accept a move order, request a plan to its place, follow it
  kFinishMove,   ///< report the move done; the place becomes the robot's home: stop and wait
  kStartSearch,  ///< start the pallet search at the pick area
  kStartPick,    ///< start visual-servoing pick on the found marker
  kPlanToDrop,   ///< report the pallet picked, request a plan to the drop area
  kStartDrop,    ///< start placing on the drop area
  kReportEmpty,  ///< report the pick area empty, end the order, request a plan home
  kFinishOrder,  ///< report the pallet dropped, end the order, request a plan home
  kCancelOrder,  ///< report the order cancelled, request a plan home
  kAbandonPick,  ///< report the order failed with the reason, request a plan home
  kStop,         ///< home reached: stop and wait
  kSuspend,      ///< stand still, remember what was interrupted
  kRestore,      ///< continue what was interrupted
  kFail,         ///< stop, report the order failed with the reason
  kClear,        ///< forget the error
  kStartItems,   ///< the arm picks the line's boxes, or drops the tour's, with the base standing
};

const char* to_string(State s);
const char* to_string(Event e);
const char* to_string(Effect e);

/// One row of the transition table. `phase` restricts the row to one order phase (TRACK_PATH is
/// used both to the pick and to the drop area); `any_phase` accepts every phase. A row with
/// `restore` goes back to the state that kSuspend interrupted instead of to `to`.
struct TransitionRow {
  State from;
  bool any_phase;
  orders::OrderPhase phase;
  Event event;
  State to;
  orders::OrderPhase to_phase;
  Effect effect;
  bool restore = false;
};

/// The whole table, in the order the rows are matched. kFault is matched for every state
/// except kError by a rule outside the table (a fault can happen anywhere).
std::span<const TransitionRow> transition_table();

/// Outcome of one event.
struct Transition {
  bool accepted = false;
  State from = State::kIdle;
  State to = State::kIdle;
  orders::OrderPhase from_phase = orders::OrderPhase::kNone;
  orders::OrderPhase to_phase = orders::OrderPhase::kNone;
  Effect effect = Effect::kNone;
  std::string reason;  ///< why rejected, or the reason the event carried (a fault, a pick given up)
};

/// The state machine itself: pure bookkeeping over the table, no timing, no I/O. Rejected
/// events change nothing and say why, so the agent can answer an order with a reason.
class TaskStateMachine {
 public:
  State state() const { return state_; }
  orders::OrderPhase phase() const { return phase_; }
  /// Reason of the last fault while in kError, else empty.
  const std::string& error_reason() const { return error_; }
  /// Orders are accepted only in IDLE and GO_HOME [Forklift thesis, section 6.4].
  /// Idle, on the way home, or waiting on the way home (WAITING with no order phase).
  bool accepts_orders() const {
    return state_ == State::kIdle || state_ == State::kGoHome ||
           (state_ == State::kWaiting && phase_ == orders::OrderPhase::kNone);
  }
  /// The state a PAUSED or WAITING machine returns to, if any.
  std::optional<State> suspended_state() const;

  /// Applies an event. `reason` is kept for kFault.
  Transition handle(Event event, const std::string& reason = {});

 private:
  struct Frame {
    State state;
    orders::OrderPhase phase;
  };
  State state_ = State::kIdle;
  orders::OrderPhase phase_ = orders::OrderPhase::kNone;
  std::vector<Frame> suspended_;  ///< kPause on top of kWaiting stacks two frames
  std::string error_;
};

}  // namespace fleet::task
