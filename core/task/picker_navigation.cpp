#include "task/picker_navigation.hpp"

#include <array>

#include "task/transition_table.hpp"

namespace fleet::task {

namespace {

using S = PickerNavigationState;
using E = PickerNavigationEvent;
using T = PickerNavigationTransition;

// [Picker thesis, section 5.3.3.1.3, Fig. 5.13]. The figure's arcs are not in the text; each row
// follows the transition's label and the simulation's walk (Picker thesis, Figs. 5.14-5.18).
constexpr std::array kTable{
    T{S::kStart, E::kStartOk, S::kWaitForJob, 1},
    T{S::kWaitForJob, E::kDisable, S::kStart, 2},
    T{S::kWaitForJob, E::kJob, S::kLocalize, 3},
    T{S::kLocalize, E::kMarkerNotFound, S::kLocalize, 4},
    T{S::kLocalize, E::kRackMarker, S::kCorrectPose, 5},
    T{S::kLocalize, E::kPalletMarker, S::kAlignToPallet, 24},
    T{S::kLocalize, E::kMarkerNeverFound, S::kFailed, 0},
    T{S::kCorrectPose, E::kPoseOkGoalElsewhere, S::kSetGlobalGoal, 6},
    T{S::kCorrectPose, E::kPoseOkGoalInAisle, S::kSetAisleGoal, 7},
    // The global leg.
    T{S::kSetGlobalGoal, E::kGoalSet, S::kCheckGlobalGoal, 8},
    T{S::kCheckGlobalGoal, E::kGoalInvalid, S::kSetGlobalGoal, 9},
    T{S::kCheckGlobalGoal, E::kGoalValid, S::kCheckGlobalHeading, 12},
    T{S::kCheckGlobalGoal, E::kNoValidGoal, S::kFailed, 0},
    T{S::kCheckGlobalHeading, E::kHeadingWrong, S::kTurnAround, 14},
    T{S::kCheckGlobalHeading, E::kHeadingOk, S::kGlobalNavigation, 16},
    // Short of the goal (blocked, slipped) the pose is suspect: localize before replanning.
    T{S::kGlobalNavigation, E::kGoalNotReached, S::kLocalize, 18},
    T{S::kGlobalNavigation, E::kGoalReached, S::kLocalize, 22},
    T{S::kGlobalNavigation, E::kHomeReached, S::kWaitForJob, 23},
    // The leg along the aisle.
    T{S::kSetAisleGoal, E::kGoalSet, S::kCheckAisleGoal, 10},
    T{S::kCheckAisleGoal, E::kGoalInvalid, S::kSetAisleGoal, 11},
    T{S::kCheckAisleGoal, E::kGoalValid, S::kCheckAisleHeading, 13},
    T{S::kCheckAisleGoal, E::kNoValidGoal, S::kFailed, 0},
    T{S::kCheckAisleHeading, E::kHeadingWrong, S::kTurnAround, 15},
    T{S::kCheckAisleHeading, E::kHeadingOk, S::kFollowAisle, 17},
    T{S::kFollowAisle, E::kGoalNotReached, S::kLocalize, 0},  // as T18 on the global leg
    T{S::kFollowAisle, E::kGoalReached, S::kLocalize, 19},
    T{S::kTurnAround, E::kTurnedOnAisleLeg, S::kSetAisleGoal, 20},
    T{S::kTurnAround, E::kTurnedOnGlobalLeg, S::kSetGlobalGoal, 21},
    // At the pallet.
    T{S::kAlignToPallet, E::kAlignedForDrop, S::kDrop, 25},
    T{S::kAlignToPallet, E::kAlignedForPick, S::kPick, 26},
    T{S::kDrop, E::kItemDropped, S::kDealign, 27},
    T{S::kDrop, E::kItemNotDropped, S::kLocalize, 28},
    T{S::kDrop, E::kArmAsksMoveForDrop, S::kMoveForDrop, 29},
    T{S::kDrop, E::kArmFailed, S::kFailed, 0},
    // T32 leads to Hough navigation in the simulation, but the real run dealigns after the pick
    // (Picker thesis, section 5.3.3.2): the robot leaves the pallet before it drives on.
    T{S::kPick, E::kItemPicked, S::kDealign, 32},
    T{S::kPick, E::kItemNotPicked, S::kLocalize, 33},
    T{S::kPick, E::kArmAsksMoveForPick, S::kMoveForPick, 34},
    T{S::kPick, E::kArmFailed, S::kFailed, 0},
    T{S::kMoveForDrop, E::kMovedForArm, S::kDrop, 35},
    T{S::kMoveForDrop, E::kArmFailed, S::kFailed, 0},
    T{S::kMoveForPick, E::kMovedForArm, S::kPick, 36},
    T{S::kMoveForPick, E::kArmFailed, S::kFailed, 0},
    // Both relocalize: the next goal (drop, next item, home) starts from a corrected pose.
    T{S::kDealign, E::kDealignedJobsDone, S::kLocalize, 30},
    T{S::kDealign, E::kDealignedJobsRemain, S::kLocalize, 31},
};

}  // namespace

const char* to_string(PickerNavigationState state) {
  switch (state) {
    case S::kStart:
      return "START";
    case S::kWaitForJob:
      return "WAIT_FOR_JOB";
    case S::kLocalize:
      return "LOCALIZE";
    case S::kCorrectPose:
      return "CORRECT_POSE";
    case S::kSetGlobalGoal:
      return "SET_GLOBAL_GOAL";
    case S::kCheckGlobalGoal:
      return "CHECK_GLOBAL_GOAL";
    case S::kCheckGlobalHeading:
      return "CHECK_GLOBAL_HEADING";
    case S::kGlobalNavigation:
      return "GLOBAL_NAVIGATION";
    case S::kSetAisleGoal:
      return "SET_AISLE_GOAL";
    case S::kCheckAisleGoal:
      return "CHECK_AISLE_GOAL";
    case S::kCheckAisleHeading:
      return "CHECK_AISLE_HEADING";
    case S::kFollowAisle:
      return "FOLLOW_AISLE";
    case S::kTurnAround:
      return "TURN_AROUND";
    case S::kAlignToPallet:
      return "ALIGN_TO_PALLET";
    case S::kDrop:
      return "DROP";
    case S::kPick:
      return "PICK";
    case S::kDealign:
      return "DEALIGN";
    case S::kMoveForPick:
      return "MOVE_FOR_PICK";
    case S::kMoveForDrop:
      return "MOVE_FOR_DROP";
    case S::kFailed:
      return "FAILED";
  }
  return "?";
}

const char* to_string(PickerNavigationEvent event) {
  switch (event) {
    case E::kStartOk:
      return "start ok";
    case E::kDisable:
      return "disable";
    case E::kJob:
      return "job";
    case E::kMarkerNotFound:
      return "marker not found";
    case E::kRackMarker:
      return "rack marker";
    case E::kPalletMarker:
      return "pallet marker";
    case E::kPoseOkGoalElsewhere:
      return "pose ok, goal elsewhere";
    case E::kPoseOkGoalInAisle:
      return "pose ok, goal in aisle";
    case E::kGoalSet:
      return "goal set";
    case E::kGoalInvalid:
      return "goal invalid";
    case E::kGoalValid:
      return "goal valid";
    case E::kHeadingWrong:
      return "heading wrong";
    case E::kHeadingOk:
      return "heading ok";
    case E::kGoalNotReached:
      return "goal not reached";
    case E::kGoalReached:
      return "goal reached";
    case E::kHomeReached:
      return "home reached";
    case E::kTurnedOnGlobalLeg:
      return "turned on global leg";
    case E::kTurnedOnAisleLeg:
      return "turned on aisle leg";
    case E::kAlignedForPick:
      return "aligned for pick";
    case E::kAlignedForDrop:
      return "aligned for drop";
    case E::kItemPicked:
      return "item picked";
    case E::kItemNotPicked:
      return "item not picked";
    case E::kArmAsksMoveForPick:
      return "arm asks move for pick";
    case E::kItemDropped:
      return "item dropped";
    case E::kItemNotDropped:
      return "item not dropped";
    case E::kArmAsksMoveForDrop:
      return "arm asks move for drop";
    case E::kMovedForArm:
      return "moved for arm";
    case E::kDealignedJobsRemain:
      return "dealigned, jobs remain";
    case E::kDealignedJobsDone:
      return "dealigned, jobs done";
    case E::kMarkerNeverFound:
      return "marker never found";
    case E::kNoValidGoal:
      return "no valid goal";
    case E::kArmFailed:
      return "arm failed";
  }
  return "?";
}

std::span<const PickerNavigationTransition> picker_navigation_table() {
  return kTable;
}

std::optional<PickerNavigationState> next_picker_navigation_state(PickerNavigationState from,
                                                                  PickerNavigationEvent event) {
  return next_state(kTable, from, event);
}

bool is_final(PickerNavigationState state) {
  return state == S::kFailed;
}

}  // namespace fleet::task
