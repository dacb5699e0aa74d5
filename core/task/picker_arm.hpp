#pragma once

#include <optional>
#include <span>

namespace fleet::task {

/// How long the arm waits for navigation to move the robot before it gives up
/// [Picker thesis, section 5.3.3.1.2, T19/T20: "Robot not moved && time > 3 min"].
inline constexpr double kArmMoveTimeoutS = 180.0;

/// The picker's arm supervisor [Picker thesis, section 5.3.3.1.2, Fig. 5.8]: a server that picks
/// or drops one box on request, localizing the box or the drop point first and asking navigation
/// to move the robot when it is out of reach. The net's places 3.0 (home pose), 7.0 (descend),
/// 8.0 (run pump) and 9.0 (ascend) serve both pick and drop; here each is split into its pick and
/// its drop state, because their outcomes differ (the pump goes on or off, the request ends
/// with or without a box on the cups) and an explicit table cannot remember which one it runs.
enum class PickerArmState {
  kStart,            ///< P1.0: reading the joints
  kWaitForCommand,   ///< P2.0: at home, waiting for a pick or drop request
  kToHomePose,       ///< P3.0 entered by T2: the arm goes to its home pose before the request
  kChooseGoal,       ///< P4.0: pick or drop?
  kLocateBox,        ///< P5.0.0: the localization machine extracts the box's coordinates
  kReachAboveBox,    ///< P5.0.1: moving 20 cm above the box's top face
  kAskMoveForPick,   ///< P5.0.2: asking navigation to move the robot closer to the box
  kWaitMoveForPick,  ///< P5.0.3: waiting for that move, up to kArmMoveTimeoutS
  kLocatePlace,      ///< P6.0.0: the localization machine extracts the drop point's coordinates
  kReachAbovePlace,  ///< P6.0.1: moving the box 20 cm above the place
  kAskMoveForDrop,   ///< P6.0.2: asking navigation to move the robot closer to the place
  kWaitMoveForDrop,  ///< P6.0.3: waiting for that move, up to kArmMoveTimeoutS
  kDescendToBox,     ///< P7.0 on a pick: the cups onto the top face
  kGrip,             ///< P8.0 on a pick: pump on
  kLiftBox,          ///< P9.0 on a pick: ascend with the box
  kHomeWithBox,      ///< P3.0 entered by T22 on a pick: back home holding the box
  kDescendToPlace,   ///< P7.0 on a drop: the box onto the place
  kRelease,          ///< P8.0 on a drop: pump off
  kAscendEmpty,      ///< P9.0 on a drop: ascend without the box
  kHomeEmpty,        ///< P3.0 entered by T22 on a drop: back home, cups free
  kAbortToHomePose,  ///< added: a failed grip returns home before the request fails
  kFailed,           ///< added: the request failed, arm at home; waiting for the next command
};

enum class PickerArmEvent {
  kJointsRead,      ///< T1: the joint positions are read
  kEnable,          ///< T2: a request arrived
  kDisable,         ///< T23: the supervisor is disabled
  kHomeReached,     ///< T3, T4, T5: the home pose is reached
  kPickRequested,   ///< T6: the request is a pick
  kDropRequested,   ///< T7: the request is a drop
  kInReach,         ///< T8, T10: the coordinates are extracted and within the arm's reach
  kOutOfReach,      ///< T9, T11: the coordinates are extracted but out of reach
  kReachedAbove,    ///< T12, T14: the trajectory above the box or place is done
  kMoveRequested,   ///< T13, T15: the move request is published to navigation
  kRobotMoved,      ///< T16, T17: navigation reports the move done
  kMoveTimedOut,    ///< T19, T20: the robot has not moved within kArmMoveTimeoutS
  kDescended,       ///< T18: the descent is done
  kPumpSwitched,    ///< T21: the pump is on (pick) or off (drop)
  kAscended,        ///< T22: the ascent is done
  kMarkerNotFound,  ///< added: localization reports no box or drop point marker
  kBoxNotHeld,      ///< added: after the lift the vacuum holds no box
};

const char* to_string(PickerArmState state);
const char* to_string(PickerArmEvent event);

struct PickerArmTransition {
  PickerArmState from;
  PickerArmEvent event;
  PickerArmState to;
  int seed_transition;  ///< the net's transition number; 0 when added beyond the net
};

/// Every transition of the arm supervisor; anything else is refused.
std::span<const PickerArmTransition> picker_arm_table();
/// The state `event` leads to from `from`, or nothing.
std::optional<PickerArmState> next_picker_arm_state(PickerArmState from, PickerArmEvent event);

}  // namespace fleet::task
