#include "task/picker_arm.hpp"

#include <array>

#include "task/transition_table.hpp"

namespace fleet::task {

namespace {

using S = PickerArmState;
using E = PickerArmEvent;
using T = PickerArmTransition;

// [Picker thesis, section 5.3.3.1.2, Fig. 5.8]; the walks follow Figs. 5.9-5.12.
constexpr std::array kTable{
    T{S::kStart, E::kJointsRead, S::kWaitForCommand, 1},
    T{S::kWaitForCommand, E::kEnable, S::kToHomePose, 2},
    T{S::kWaitForCommand, E::kDisable, S::kStart, 23},
    T{S::kToHomePose, E::kHomeReached, S::kChooseGoal, 5},
    T{S::kChooseGoal, E::kPickRequested, S::kLocateBox, 6},
    T{S::kChooseGoal, E::kDropRequested, S::kLocatePlace, 7},
    // The pick.
    T{S::kLocateBox, E::kInReach, S::kReachAboveBox, 8},
    T{S::kLocateBox, E::kOutOfReach, S::kAskMoveForPick, 9},
    T{S::kLocateBox, E::kMarkerNotFound, S::kFailed, 0},
    T{S::kAskMoveForPick, E::kMoveRequested, S::kWaitMoveForPick, 13},
    T{S::kWaitMoveForPick, E::kRobotMoved, S::kLocateBox, 17},
    // The net leaves T19's output unsaid; the arm is still at home, so the request fails there.
    T{S::kWaitMoveForPick, E::kMoveTimedOut, S::kFailed, 19},
    T{S::kReachAboveBox, E::kReachedAbove, S::kDescendToBox, 12},
    T{S::kDescendToBox, E::kDescended, S::kGrip, 18},
    T{S::kGrip, E::kPumpSwitched, S::kLiftBox, 21},
    T{S::kLiftBox, E::kAscended, S::kHomeWithBox, 22},
    // The thesis names a box not grasped properly as a failure to retry; navigation retries (T33).
    T{S::kLiftBox, E::kBoxNotHeld, S::kAbortToHomePose, 0},
    T{S::kAbortToHomePose, E::kHomeReached, S::kFailed, 0},
    T{S::kHomeWithBox, E::kHomeReached, S::kWaitForCommand, 3},
    // The drop.
    T{S::kLocatePlace, E::kInReach, S::kReachAbovePlace, 10},
    T{S::kLocatePlace, E::kOutOfReach, S::kAskMoveForDrop, 11},
    T{S::kLocatePlace, E::kMarkerNotFound, S::kFailed, 0},
    T{S::kAskMoveForDrop, E::kMoveRequested, S::kWaitMoveForDrop, 15},
    T{S::kWaitMoveForDrop, E::kRobotMoved, S::kLocatePlace, 16},
    T{S::kWaitMoveForDrop, E::kMoveTimedOut, S::kFailed, 20},
    T{S::kReachAbovePlace, E::kReachedAbove, S::kDescendToPlace, 14},
    T{S::kDescendToPlace, E::kDescended, S::kRelease, 18},
    T{S::kRelease, E::kPumpSwitched, S::kAscendEmpty, 21},
    T{S::kAscendEmpty, E::kAscended, S::kHomeEmpty, 22},
    T{S::kHomeEmpty, E::kHomeReached, S::kWaitForCommand, 4},
    // A failed request leaves the arm at home: it takes the next request like kWaitForCommand.
    T{S::kFailed, E::kEnable, S::kToHomePose, 0},
    T{S::kFailed, E::kDisable, S::kStart, 0},
};

}  // namespace

const char* to_string(PickerArmState state) {
  switch (state) {
    case S::kStart:
      return "START";
    case S::kWaitForCommand:
      return "WAIT_FOR_COMMAND";
    case S::kToHomePose:
      return "TO_HOME_POSE";
    case S::kChooseGoal:
      return "CHOOSE_GOAL";
    case S::kLocateBox:
      return "LOCATE_BOX";
    case S::kReachAboveBox:
      return "REACH_ABOVE_BOX";
    case S::kAskMoveForPick:
      return "ASK_MOVE_FOR_PICK";
    case S::kWaitMoveForPick:
      return "WAIT_MOVE_FOR_PICK";
    case S::kLocatePlace:
      return "LOCATE_PLACE";
    case S::kReachAbovePlace:
      return "REACH_ABOVE_PLACE";
    case S::kAskMoveForDrop:
      return "ASK_MOVE_FOR_DROP";
    case S::kWaitMoveForDrop:
      return "WAIT_MOVE_FOR_DROP";
    case S::kDescendToBox:
      return "DESCEND_TO_BOX";
    case S::kGrip:
      return "GRIP";
    case S::kLiftBox:
      return "LIFT_BOX";
    case S::kHomeWithBox:
      return "HOME_WITH_BOX";
    case S::kDescendToPlace:
      return "DESCEND_TO_PLACE";
    case S::kRelease:
      return "RELEASE";
    case S::kAscendEmpty:
      return "ASCEND_EMPTY";
    case S::kHomeEmpty:
      return "HOME_EMPTY";
    case S::kAbortToHomePose:
      return "ABORT_TO_HOME_POSE";
    case S::kFailed:
      return "FAILED";
  }
  return "?";
}

const char* to_string(PickerArmEvent event) {
  switch (event) {
    case E::kJointsRead:
      return "joints read";
    case E::kEnable:
      return "enable";
    case E::kDisable:
      return "disable";
    case E::kHomeReached:
      return "home reached";
    case E::kPickRequested:
      return "pick requested";
    case E::kDropRequested:
      return "drop requested";
    case E::kInReach:
      return "in reach";
    case E::kOutOfReach:
      return "out of reach";
    case E::kReachedAbove:
      return "reached above";
    case E::kMoveRequested:
      return "move requested";
    case E::kRobotMoved:
      return "robot moved";
    case E::kMoveTimedOut:
      return "move timed out";
    case E::kDescended:
      return "descended";
    case E::kPumpSwitched:
      return "pump switched";
    case E::kAscended:
      return "ascended";
    case E::kMarkerNotFound:
      return "marker not found";
    case E::kBoxNotHeld:
      return "box not held";
  }
  return "?";
}

std::span<const PickerArmTransition> picker_arm_table() {
  return kTable;
}

std::optional<PickerArmState> next_picker_arm_state(PickerArmState from, PickerArmEvent event) {
  return next_state(kTable, from, event);
}

}  // namespace fleet::task
