#pragma once

#include <optional>
#include <span>

namespace fleet::task {

/// The picker's navigation supervisor [Picker thesis, section 5.3.3.1.3, Fig. 5.13]: the global
/// supervisor that takes a WMS job (pick point, drop point, item count), localizes, drives
/// globally and along the aisle, aligns to pallets and asks the arm to pick and drop. The net's
/// 17 places are the states below, except that place 4.0 (correct pose) is split by the role its
/// token plays: correcting the pose after a localization, or moving for the arm [T29, T34]. An
/// explicit table cannot remember why it entered a place, so the split keeps "move for the arm"
/// from being answered with "go on to the global goal".
enum class PickerNavigationState {
  kStart,               ///< P1.0: start-up checks
  kWaitForJob,          ///< P2.0: idle at home, waiting for a WMS job
  kLocalize,            ///< P3.0: the localization machine looks for a rack or pallet marker
  kCorrectPose,         ///< P4.0: the pose is corrected in the map from a rack marker
  kSetGlobalGoal,       ///< P5.0: the planner gets the start point and the goal
  kCheckGlobalGoal,     ///< P5.1: both are checked against the map
  kCheckGlobalHeading,  ///< P5.2: does the robot face the way the path leaves?
  kGlobalNavigation,    ///< P5.3: following the global path's waypoints
  kSetAisleGoal,        ///< P6.0: start and goal along the aisle (pick or drop point)
  kCheckAisleGoal,      ///< P6.1: both are checked against the aisle
  kCheckAisleHeading,   ///< P6.2: does the robot face the way along the aisle it must go?
  kFollowAisle,         ///< P6.3: Hough-line aisle following to the goal
  kTurnAround,          ///< P7.0: turning 180° in place
  kAlignToPallet,       ///< P8.0: moving close to and parallel with the pallet
  kDrop,                ///< P9.0: the arm machine drops the box; navigation waits
  kPick,                ///< P10.0: the arm machine picks a box; navigation waits
  kDealign,             ///< P11.0: backing away from the pallet to the aisle's following line
  kMoveForPick,         ///< P4.0 entered by T34: the arm asked for a move to bring the box into reach
  kMoveForDrop,         ///< P4.0 entered by T29: the arm asked for a move to bring the place into reach
  kFailed,              ///< added: the job is given up; the reason is the event that led here
};

/// What moves the navigation machine. The token conditions of the net (jobs remaining, heading,
/// goal valid, which leg the goal needs, the marker class found) are explicit events: the owner
/// that knows the job raises the one that holds.
enum class PickerNavigationEvent {
  kStartOk,              ///< T1: start-up checks passed
  kDisable,              ///< T2: the supervisor is disabled
  kJob,                  ///< T3: enabled and a WMS job with items to fetch arrived
  kMarkerNotFound,       ///< T4: localization found no marker: ask it again
  kRackMarker,           ///< T5: localization found the rack marker sought
  kPalletMarker,         ///< T24: localization found the pallet marker sought
  kPoseOkGoalElsewhere,  ///< T6: pose corrected; the goal is in another aisle (or home)
  kPoseOkGoalInAisle,    ///< T7: pose corrected; the goal is along this aisle
  kGoalSet,              ///< T8, T10: start and goal handed to the planner
  kGoalInvalid,          ///< T9, T11: start or goal not valid: set them again
  kGoalValid,            ///< T12, T13: start and goal valid
  kHeadingWrong,         ///< T14, T15: the robot faces away from where it must go
  kHeadingOk,            ///< T16, T17: the robot faces the way to go
  kGoalNotReached,       ///< T18: the motion ended short of its goal: localize and replan
  kGoalReached,          ///< T19, T22: the goal (a rack or a pallet) is reached
  kHomeReached,          ///< T23: the goal home is reached
  kTurnedOnGlobalLeg,    ///< T21: turned; the leg is a global one
  kTurnedOnAisleLeg,     ///< T20: turned; the leg is along the aisle
  kAlignedForPick,       ///< T26: aligned to the pick pallet
  kAlignedForDrop,       ///< T25: aligned to the drop pallet
  kItemPicked,           ///< T32: the arm picked the box
  kItemNotPicked,        ///< T33: the arm failed the pick: localize the pallet and try again
  kArmAsksMoveForPick,   ///< T34: the box is out of reach: the arm asks for a move
  kItemDropped,          ///< T27: the arm put the box down
  kItemNotDropped,       ///< T28: the arm failed the drop: localize the pallet and try again
  kArmAsksMoveForDrop,   ///< T29: the place is out of reach: the arm asks for a move
  kMovedForArm,          ///< T35, T36: the move is done: the arm tries again
  kDealignedJobsRemain,  ///< T31: dealigned; a box is carried or items remain to fetch
  kDealignedJobsDone,    ///< T30: dealigned after the last item's drop: go home
  kMarkerNeverFound,     ///< added: localization keeps finding no marker: the job fails
  kNoValidGoal,          ///< added: the planner keeps refusing start or goal: the job fails
  kArmFailed,            ///< added: the arm gave up (marker, reach, 3-minute move timeout)
};

const char* to_string(PickerNavigationState state);
const char* to_string(PickerNavigationEvent event);

struct PickerNavigationTransition {
  PickerNavigationState from;
  PickerNavigationEvent event;
  PickerNavigationState to;
  int seed_transition;  ///< the net's transition number; 0 when added beyond the net
};

/// Every transition of the navigation supervisor; anything else is refused.
std::span<const PickerNavigationTransition> picker_navigation_table();
/// The state `event` leads to from `from`, or nothing.
std::optional<PickerNavigationState> next_picker_navigation_state(PickerNavigationState from,
                                                                  PickerNavigationEvent event);
/// Whether nothing leads out of `state` (only kFailed: an operator restarts the supervisor at kStart).
bool is_final(PickerNavigationState state);

}  // namespace fleet::task
