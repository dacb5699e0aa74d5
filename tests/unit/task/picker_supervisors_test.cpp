#include "task/picker_supervisors.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <set>
#include <utility>
#include <vector>

#include "task/transition_table.hpp"

namespace fleet::task {
namespace {

using Nav = PickerNavigationState;
using NavEvent = PickerNavigationEvent;
using Arm = PickerArmState;
using ArmEvent = PickerArmEvent;
using Loc = PickerLocalizationState;
using LocEvent = PickerLocalizationEvent;

// The enums are contiguous from 0; the last enumerator bounds them.
template <typename Enum>
std::vector<Enum> all_up_to(Enum last) {
  std::vector<Enum> all;
  for (int i = 0; i <= static_cast<int>(last); ++i) all.push_back(static_cast<Enum>(i));
  return all;
}

template <typename Row, typename State, typename Event>
void expect_rows_unique_and_alone(std::span<const Row> table, std::optional<State> (*next)(State, Event),
                                  State last_state, Event last_event) {
  for (const Row& t : repeated_rows(table))
    ADD_FAILURE() << to_string(t.from) << " on " << to_string(t.event) << " listed twice";
  std::set<std::pair<int, int>> rows;
  for (const Row& t : table) {
    rows.insert({static_cast<int>(t.from), static_cast<int>(t.event)});
    EXPECT_EQ(next(t.from, t.event), t.to) << to_string(t.from) << " on " << to_string(t.event);
  }
  for (State s : all_up_to(last_state)) {
    for (Event e : all_up_to(last_event)) {
      if (!rows.contains({static_cast<int>(s), static_cast<int>(e)})) {
        EXPECT_FALSE(next(s, e)) << to_string(s) << " on " << to_string(e);
      }
    }
  }
}

template <typename Row, typename State>
void expect_all_reachable(std::span<const Row> table, State start, State last_state) {
  const std::set<State> seen = reachable_states(table, start);
  for (State s : all_up_to(last_state)) EXPECT_TRUE(seen.contains(s)) << to_string(s) << " unreachable";
}

template <typename Row, typename State>
void expect_ways_out(std::span<const Row> table, State last_state, std::set<State> finals) {
  for (State s : all_up_to(last_state)) {
    bool out = false;
    for (const Row& t : table) out = out || (t.from == s && t.to != s);
    EXPECT_EQ(out, !finals.contains(s)) << to_string(s);
  }
}

// Every transition of the seed's net is a row; rows added beyond it carry 0.
template <typename Row>
void expect_seed_transitions(std::span<const Row> table, int count) {
  std::set<int> seed;
  for (const Row& t : table) {
    if (t.seed_transition != 0) seed.insert(t.seed_transition);
  }
  EXPECT_EQ(seed.size(), static_cast<std::size_t>(count));
  EXPECT_EQ(*seed.begin(), 1);
  EXPECT_EQ(*seed.rbegin(), count);
}

template <typename State, typename Event>
void walk(State& s, std::optional<State> (*next)(State, Event), const std::vector<std::pair<Event, State>>& steps) {
  for (const auto& [event, to] : steps) {
    const std::optional<State> n = next(s, event);
    ASSERT_TRUE(n) << to_string(s) << " refuses " << to_string(event);
    ASSERT_EQ(*n, to) << to_string(s) << " on " << to_string(event) << " leads to " << to_string(*n) << ", not "
                      << to_string(to);
    s = *n;
  }
}

void nav(Nav& s, const std::vector<std::pair<NavEvent, Nav>>& steps) {
  walk(s, next_picker_navigation_state, steps);
}
void arm(Arm& s, const std::vector<std::pair<ArmEvent, Arm>>& steps) {
  walk(s, next_picker_arm_state, steps);
}
void loc(Loc& s, const std::vector<std::pair<LocEvent, Loc>>& steps) {
  walk(s, next_picker_localization_state, steps);
}

// Localize at a rack marker, then plan and drive a leg: global (to another aisle) or along the aisle.
void localize_and_drive_global(Nav& s, NavEvent arrival) {
  nav(s, {{NavEvent::kRackMarker, Nav::kCorrectPose},
          {NavEvent::kPoseOkGoalElsewhere, Nav::kSetGlobalGoal},
          {NavEvent::kGoalSet, Nav::kCheckGlobalGoal},
          {NavEvent::kGoalValid, Nav::kCheckGlobalHeading},
          {NavEvent::kHeadingOk, Nav::kGlobalNavigation},
          {arrival, arrival == NavEvent::kHomeReached ? Nav::kWaitForJob : Nav::kLocalize}});
}
void localize_and_follow_aisle(Nav& s) {
  nav(s, {{NavEvent::kRackMarker, Nav::kCorrectPose},
          {NavEvent::kPoseOkGoalInAisle, Nav::kSetAisleGoal},
          {NavEvent::kGoalSet, Nav::kCheckAisleGoal},
          {NavEvent::kGoalValid, Nav::kCheckAisleHeading},
          {NavEvent::kHeadingOk, Nav::kFollowAisle},
          {NavEvent::kGoalReached, Nav::kLocalize},
          {NavEvent::kPalletMarker, Nav::kAlignToPallet}});
}

TEST(PickerSupervisors, EveryRowIsTheOnlyWayFromItsStateOnItsEvent) {
  expect_rows_unique_and_alone(picker_navigation_table(), next_picker_navigation_state, Nav::kFailed,
                               NavEvent::kArmFailed);
  expect_rows_unique_and_alone(picker_arm_table(), next_picker_arm_state, Arm::kFailed, ArmEvent::kBoxNotHeld);
  expect_rows_unique_and_alone(picker_localization_table(), next_picker_localization_state, Loc::kReportNoMarker,
                               LocEvent::kMessageSent);
}

TEST(PickerSupervisors, EveryStateIsReachableFromTheStart) {
  expect_all_reachable(picker_navigation_table(), Nav::kStart, Nav::kFailed);
  expect_all_reachable(picker_arm_table(), Arm::kStart, Arm::kFailed);
  expect_all_reachable(picker_localization_table(), Loc::kStart, Loc::kReportNoMarker);
}

TEST(PickerSupervisors, OnlyAFailedJobEndsTheNavigationEveryOtherStateHasAWayOut) {
  expect_ways_out(picker_navigation_table(), Nav::kFailed, {Nav::kFailed});
  EXPECT_TRUE(is_final(Nav::kFailed));
  // The arm and localization are servers: a failed request waits for the next one.
  expect_ways_out(picker_arm_table(), Arm::kFailed, std::set<Arm>{});
  expect_ways_out(picker_localization_table(), Loc::kReportNoMarker, std::set<Loc>{});
}

TEST(PickerSupervisors, EveryTransitionOfTheSeedsNetsIsARow) {
  expect_seed_transitions(picker_navigation_table(), 36);
  expect_seed_transitions(picker_arm_table(), 23);
  expect_seed_transitions(picker_localization_table(), 38);
}

TEST(PickerSupervisors, NavigationWalksAJobOfTwoItemsFromHomeBackHome) {
  Nav s = Nav::kStart;
  nav(s, {{NavEvent::kStartOk, Nav::kWaitForJob}, {NavEvent::kJob, Nav::kLocalize}});
  localize_and_drive_global(s, NavEvent::kGoalReached);  // to the pick aisle
  // The robot entered the aisle facing away from the pick point: it turns and plans again.
  nav(s, {{NavEvent::kRackMarker, Nav::kCorrectPose},
          {NavEvent::kPoseOkGoalInAisle, Nav::kSetAisleGoal},
          {NavEvent::kGoalSet, Nav::kCheckAisleGoal},
          {NavEvent::kGoalValid, Nav::kCheckAisleHeading},
          {NavEvent::kHeadingWrong, Nav::kTurnAround},
          {NavEvent::kTurnedOnAisleLeg, Nav::kSetAisleGoal},
          {NavEvent::kGoalSet, Nav::kCheckAisleGoal},
          {NavEvent::kGoalValid, Nav::kCheckAisleHeading},
          {NavEvent::kHeadingOk, Nav::kFollowAisle},
          {NavEvent::kGoalReached, Nav::kLocalize},
          {NavEvent::kPalletMarker, Nav::kAlignToPallet}});
  // One box at a time: the gripper holds one, so two items are two pick-and-drop rounds.
  for (int item = 1; item <= 2; ++item) {
    if (item == 2) {
      nav(s, {{NavEvent::kDealignedJobsRemain, Nav::kLocalize}});
      localize_and_follow_aisle(s);  // back to the pick pallet
    }
    nav(s, {{NavEvent::kAlignedForPick, Nav::kPick},
            {NavEvent::kItemPicked, Nav::kDealign},
            {NavEvent::kDealignedJobsRemain, Nav::kLocalize}});
    localize_and_follow_aisle(s);  // to the drop pallet, in the same aisle
    nav(s, {{NavEvent::kAlignedForDrop, Nav::kDrop}, {NavEvent::kItemDropped, Nav::kDealign}});
  }
  nav(s, {{NavEvent::kDealignedJobsDone, Nav::kLocalize}});
  localize_and_drive_global(s, NavEvent::kHomeReached);
  EXPECT_EQ(s, Nav::kWaitForJob);
}

TEST(PickerSupervisors, ABoxOutOfReachMakesTheArmAskNavigationToMoveThenThePickSucceeds) {
  Nav n = Nav::kAlignToPallet;
  Arm a = Arm::kStart;
  Loc l = Loc::kStart;
  arm(a, {{ArmEvent::kJointsRead, Arm::kWaitForCommand}});
  loc(l, {{LocEvent::kReady, Loc::kWaitForCommand}});
  // The box's marker, seen by the right depth camera on its pan-tilt unit.
  const std::vector<std::pair<LocEvent, Loc>> locate_box = {{LocEvent::kScanRightDepthRequested, Loc::kScanRightDepth},
                                                            {LocEvent::kScanDone, Loc::kEvaluateRightDepth},
                                                            {LocEvent::kMarkerSeen, Loc::kExtractMarker},
                                                            {LocEvent::kBoxMarkerSeen, Loc::kCheckBoxId},
                                                            {LocEvent::kIdSought, Loc::kPublishMarker},
                                                            {LocEvent::kPublished, Loc::kWaitForCommand}};

  nav(n, {{NavEvent::kAlignedForPick, Nav::kPick}});
  arm(a, {{ArmEvent::kEnable, Arm::kToHomePose},
          {ArmEvent::kHomeReached, Arm::kChooseGoal},
          {ArmEvent::kPickRequested, Arm::kLocateBox}});
  loc(l, locate_box);
  arm(a, {{ArmEvent::kOutOfReach, Arm::kAskMoveForPick}, {ArmEvent::kMoveRequested, Arm::kWaitMoveForPick}});
  nav(n, {{NavEvent::kArmAsksMoveForPick, Nav::kMoveForPick}, {NavEvent::kMovedForArm, Nav::kPick}});
  arm(a, {{ArmEvent::kRobotMoved, Arm::kLocateBox}});
  loc(l, locate_box);
  arm(a, {{ArmEvent::kInReach, Arm::kReachAboveBox},
          {ArmEvent::kReachedAbove, Arm::kDescendToBox},
          {ArmEvent::kDescended, Arm::kGrip},
          {ArmEvent::kPumpSwitched, Arm::kLiftBox},
          {ArmEvent::kAscended, Arm::kHomeWithBox},
          {ArmEvent::kHomeReached, Arm::kWaitForCommand}});
  nav(n, {{NavEvent::kItemPicked, Nav::kDealign}});
  EXPECT_EQ(n, Nav::kDealign);
}

TEST(PickerSupervisors, APlaceOutOfReachIsDroppedAfterTheMove) {
  Nav n = Nav::kAlignToPallet;
  Arm a = Arm::kWaitForCommand;
  nav(n, {{NavEvent::kAlignedForDrop, Nav::kDrop}});
  arm(a, {{ArmEvent::kEnable, Arm::kToHomePose},
          {ArmEvent::kHomeReached, Arm::kChooseGoal},
          {ArmEvent::kDropRequested, Arm::kLocatePlace},
          {ArmEvent::kOutOfReach, Arm::kAskMoveForDrop},
          {ArmEvent::kMoveRequested, Arm::kWaitMoveForDrop}});
  nav(n, {{NavEvent::kArmAsksMoveForDrop, Nav::kMoveForDrop}, {NavEvent::kMovedForArm, Nav::kDrop}});
  arm(a, {{ArmEvent::kRobotMoved, Arm::kLocatePlace},
          {ArmEvent::kInReach, Arm::kReachAbovePlace},
          {ArmEvent::kReachedAbove, Arm::kDescendToPlace},
          {ArmEvent::kDescended, Arm::kRelease},
          {ArmEvent::kPumpSwitched, Arm::kAscendEmpty},
          {ArmEvent::kAscended, Arm::kHomeEmpty},
          {ArmEvent::kHomeReached, Arm::kWaitForCommand}});
  nav(n, {{NavEvent::kItemDropped, Nav::kDealign}});
  EXPECT_EQ(n, Nav::kDealign);
}

TEST(PickerSupervisors, ARackMarkerNeverFoundFailsTheJobWithThatReason) {
  Nav n = Nav::kWaitForJob;
  Loc l = Loc::kWaitForCommand;
  // Both RGB cameras: a quick scan, a step-mode rescan, then "no marker found" to the caller.
  const std::vector<std::pair<LocEvent, Loc>> scan_and_miss = {
      {LocEvent::kScanBothRgbRequested, Loc::kScanBothRgb}, {LocEvent::kScanDone, Loc::kEvaluateBothRgb},
      {LocEvent::kQuickScanMissed, Loc::kScanBothRgb},      {LocEvent::kScanDone, Loc::kEvaluateBothRgb},
      {LocEvent::kStepScanMissed, Loc::kReportNoMarker},    {LocEvent::kMessageSent, Loc::kWaitForCommand}};
  nav(n, {{NavEvent::kJob, Nav::kLocalize}});
  loc(l, scan_and_miss);
  nav(n, {{NavEvent::kMarkerNotFound, Nav::kLocalize}});  // asks again
  loc(l, scan_and_miss);
  const NavEvent why = NavEvent::kMarkerNeverFound;  // the owner's retries are used up
  nav(n, {{why, Nav::kFailed}});
  EXPECT_STREQ(to_string(why), "marker never found");
  for (NavEvent e : all_up_to(NavEvent::kArmFailed)) EXPECT_FALSE(next_picker_navigation_state(n, e));
}

TEST(PickerSupervisors, ARobotThatDoesNotMoveWithinThreeMinutesFailsThePick) {
  EXPECT_EQ(kArmMoveTimeoutS, 180.0);
  Nav n = Nav::kPick;
  Arm a = Arm::kLocateBox;
  arm(a, {{ArmEvent::kOutOfReach, Arm::kAskMoveForPick},
          {ArmEvent::kMoveRequested, Arm::kWaitMoveForPick},
          {ArmEvent::kMoveTimedOut, Arm::kFailed}});
  nav(n, {{NavEvent::kArmAsksMoveForPick, Nav::kMoveForPick}, {NavEvent::kArmFailed, Nav::kFailed}});
  // The failed arm takes the next request.
  arm(a, {{ArmEvent::kEnable, Arm::kToHomePose}});
}

TEST(PickerSupervisors, ABoxNotHeldGoesHomeFailsThePickAndNavigationTriesAgain) {
  Nav n = Nav::kPick;
  Arm a = Arm::kLiftBox;
  arm(a, {{ArmEvent::kBoxNotHeld, Arm::kAbortToHomePose}, {ArmEvent::kHomeReached, Arm::kFailed}});
  nav(n, {{NavEvent::kItemNotPicked, Nav::kLocalize},
          {NavEvent::kPalletMarker, Nav::kAlignToPallet},
          {NavEvent::kAlignedForPick, Nav::kPick}});
}

TEST(PickerSupervisors, AWrongBoxIdRescansWithTheSameCameraThenCountsAsNoMarker) {
  Loc l = Loc::kWaitForCommand;
  loc(l, {{LocEvent::kScanLeftDepthRequested, Loc::kScanLeftDepth},
          {LocEvent::kScanDone, Loc::kEvaluateLeftDepth},
          {LocEvent::kMarkerSeen, Loc::kExtractMarker},
          {LocEvent::kBoxMarkerSeen, Loc::kCheckBoxId},
          {LocEvent::kWrongBoxIdLeftCamera, Loc::kScanLeftDepth},
          {LocEvent::kScanDone, Loc::kEvaluateLeftDepth},
          {LocEvent::kMarkerSeen, Loc::kExtractMarker},
          {LocEvent::kBoxMarkerSeen, Loc::kCheckBoxId},
          {LocEvent::kWrongIdAgain, Loc::kReportNoMarker},
          {LocEvent::kMessageSent, Loc::kWaitForCommand}});
}

}  // namespace
}  // namespace fleet::task
