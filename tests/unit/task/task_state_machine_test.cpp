#include "task/task_state_machine.hpp"

#include <gtest/gtest.h>

#include <set>
#include <tuple>
#include <vector>

namespace fleet::task {
namespace {

using orders::OrderPhase;

const std::vector<State> kAllStates = {State::kIdle,       State::kTrackPath, State::kSearchPallet, State::kPickPallet,
                                       State::kDropPallet, State::kPickItems, State::kDropItems,    State::kGoHome,
                                       State::kWaiting,    State::kPaused,    State::kError};

void expect(TaskStateMachine& m, Event e, State to, OrderPhase phase, Effect effect) {
  const State from = m.state();
  const Transition tr = m.handle(e);
  ASSERT_TRUE(tr.accepted) << to_string(e) << " in " << to_string(from) << ": " << tr.reason;
  EXPECT_EQ(tr.to, to) << to_string(e) << " in " << to_string(from);
  EXPECT_EQ(m.state(), to);
  EXPECT_EQ(m.phase(), phase) << to_string(e) << " in " << to_string(from);
  EXPECT_EQ(tr.effect, effect) << to_string(e) << " in " << to_string(from);
}

/// Drives a fresh machine into `target` along accepted events (for the rejection tests).
TaskStateMachine machine_in(State target) {
  TaskStateMachine m;
  auto go = [&](Event e) { EXPECT_TRUE(m.handle(e).accepted) << to_string(e); };
  switch (target) {
    case State::kIdle:
      break;
    case State::kTrackPath:
      go(Event::kOrder);
      break;
    case State::kSearchPallet:
      go(Event::kOrder);
      go(Event::kPathEnded);
      break;
    case State::kPickPallet:
      go(Event::kOrder);
      go(Event::kPathEnded);
      go(Event::kPalletFound);
      break;
    case State::kDropPallet:
      go(Event::kOrder);
      go(Event::kPathEnded);
      go(Event::kPalletFound);
      go(Event::kPickDone);
      go(Event::kPathEnded);
      break;
    case State::kPickItems:
      go(Event::kOrder);
      go(Event::kAtItems);
      break;
    case State::kDropItems:
      go(Event::kOrder);
      go(Event::kAtItems);
      go(Event::kTourPicked);
      go(Event::kAtItems);
      break;
    case State::kGoHome:
      go(Event::kOrder);
      go(Event::kPathEnded);
      go(Event::kAreaEmpty);
      break;
    case State::kWaiting:
      go(Event::kOrder);
      go(Event::kBlocked);
      break;
    case State::kPaused:
      go(Event::kPause);
      break;
    case State::kError:
      m.handle(Event::kFault, "test");
      break;
  }
  EXPECT_EQ(m.state(), target);
  return m;
}

TEST(TaskStateMachine, HappyPathOfFig69) {
  TaskStateMachine m;
  EXPECT_EQ(m.state(), State::kIdle);
  EXPECT_EQ(m.phase(), OrderPhase::kNone);
  expect(m, Event::kOrder, State::kTrackPath, OrderPhase::kToPick, Effect::kPlanToPick);
  expect(m, Event::kPathEnded, State::kSearchPallet, OrderPhase::kSearching, Effect::kStartSearch);
  expect(m, Event::kPalletFound, State::kPickPallet, OrderPhase::kPicking, Effect::kStartPick);
  expect(m, Event::kPickDone, State::kTrackPath, OrderPhase::kToDrop, Effect::kPlanToDrop);
  expect(m, Event::kPathEnded, State::kDropPallet, OrderPhase::kDropping, Effect::kStartDrop);
  expect(m, Event::kDropDone, State::kGoHome, OrderPhase::kNone, Effect::kFinishOrder);
  expect(m, Event::kHomeReached, State::kIdle, OrderPhase::kNone, Effect::kStop);
}

// A pick order [Picker thesis, section 5.3.3.1.1]: beside each line's place the arm takes its
// boxes, then at the drop place it puts them all down; boxes on the tray are never cancelled.
TEST(TaskStateMachine, APickTourVisitsEachLineThenDropsEverything) {
  TaskStateMachine m;
  expect(m, Event::kOrder, State::kTrackPath, OrderPhase::kToPick, Effect::kPlanToPick);
  expect(m, Event::kAtItems, State::kPickItems, OrderPhase::kPicking, Effect::kStartItems);
  expect(m, Event::kItemsPicked, State::kTrackPath, OrderPhase::kToPick, Effect::kPlanToPick);
  expect(m, Event::kAtItems, State::kPickItems, OrderPhase::kPicking, Effect::kStartItems);
  EXPECT_FALSE(m.handle(Event::kCancel).accepted) << "boxes on the tray";
  expect(m, Event::kTourPicked, State::kTrackPath, OrderPhase::kToDrop, Effect::kPlanToDrop);
  EXPECT_FALSE(m.handle(Event::kCancel).accepted) << "boxes on the tray";
  expect(m, Event::kAtItems, State::kDropItems, OrderPhase::kDropping, Effect::kStartItems);
  expect(m, Event::kItemsDropped, State::kGoHome, OrderPhase::kNone, Effect::kFinishOrder);

  // A loader's boxes are on its transporters' pallets: its walk ends at the last place.
  TaskStateMachine loader;
  expect(loader, Event::kOrder, State::kTrackPath, OrderPhase::kToPick, Effect::kPlanToPick);
  expect(loader, Event::kAtItems, State::kPickItems, OrderPhase::kPicking, Effect::kStartItems);
  // At a stop it drove to ahead of its release, its transporter replaced: it makes way.
  expect(loader, Event::kStopWithdrawn, State::kTrackPath, OrderPhase::kToPick, Effect::kPlanToPick);
  expect(loader, Event::kAtItems, State::kPickItems, OrderPhase::kPicking, Effect::kStartItems);
  expect(loader, Event::kWalkLoaded, State::kGoHome, OrderPhase::kNone, Effect::kFinishOrder);

  TaskStateMachine failing = machine_in(State::kDropItems);
  const Transition tr = failing.handle(Event::kItemsFailed, "box 2 of A1 onto the pallet: out of reach");
  EXPECT_EQ(tr.to, State::kError);
  EXPECT_EQ(failing.error_reason(), "box 2 of A1 onto the pallet: out of reach");
}

TEST(TaskStateMachine, EmptyAreaGoesHomeAndAcceptsOrdersOnTheWay) {
  TaskStateMachine m = machine_in(State::kSearchPallet);
  expect(m, Event::kAreaEmpty, State::kGoHome, OrderPhase::kNone, Effect::kReportEmpty);
  EXPECT_TRUE(m.accepts_orders());
  expect(m, Event::kOrder, State::kTrackPath, OrderPhase::kToPick, Effect::kPlanToPick);
}

TEST(TaskStateMachine, OrdersAcceptedOnlyInIdleAndGoHome) {
  for (State s : kAllStates) {
    TaskStateMachine m = machine_in(s);
    const OrderPhase phase_before = m.phase();
    const Transition tr = m.handle(Event::kOrder);
    // machine_in(kWaiting) waits on its way to a pick: no order then.
    const bool should = s == State::kIdle || s == State::kGoHome;
    EXPECT_EQ(tr.accepted, should) << to_string(s);
    EXPECT_EQ(m.accepts_orders() || tr.accepted, should) << to_string(s);
    if (!should) {
      EXPECT_EQ(m.state(), s) << "a rejected order changes nothing";
      EXPECT_EQ(m.phase(), phase_before);
      EXPECT_NE(tr.reason.find(to_string(s)), std::string::npos) << tr.reason;
    }
  }
}

// Regression: a robot waiting for traffic on its way home rejected the orders the server offered
// it as a robot going home ("order not accepted in WAITING"), several a minute in a demo.
TEST(TaskStateMachine, WaitingOnTheWayHomeAcceptsAnOrderWaitingInOneDoesNot) {
  TaskStateMachine going_home = machine_in(State::kGoHome);
  expect(going_home, Event::kBlocked, State::kWaiting, OrderPhase::kNone, Effect::kSuspend);
  EXPECT_TRUE(going_home.accepts_orders());
  expect(going_home, Event::kOrder, State::kTrackPath, OrderPhase::kToPick, Effect::kPlanToPick);

  TaskStateMachine on_an_order = machine_in(State::kWaiting);
  ASSERT_EQ(on_an_order.phase(), OrderPhase::kToPick);
  EXPECT_FALSE(on_an_order.accepts_orders());
  EXPECT_FALSE(on_an_order.handle(Event::kOrder).accepted);
}

TEST(TaskStateMachine, PauseAndResumeRestoreStateAndPhase) {
  TaskStateMachine m = machine_in(State::kPickPallet);
  expect(m, Event::kPause, State::kPaused, OrderPhase::kPicking, Effect::kSuspend);
  EXPECT_EQ(m.suspended_state(), State::kPickPallet);
  EXPECT_FALSE(m.handle(Event::kPickDone).accepted) << "a paused machine ignores controller events";
  expect(m, Event::kResume, State::kPickPallet, OrderPhase::kPicking, Effect::kRestore);
}

TEST(TaskStateMachine, WaitingNestsUnderPause) {
  TaskStateMachine m = machine_in(State::kTrackPath);
  expect(m, Event::kBlocked, State::kWaiting, OrderPhase::kToPick, Effect::kSuspend);
  expect(m, Event::kPause, State::kPaused, OrderPhase::kToPick, Effect::kSuspend);
  EXPECT_FALSE(m.handle(Event::kUnblocked).accepted);
  expect(m, Event::kResume, State::kWaiting, OrderPhase::kToPick, Effect::kRestore);
  expect(m, Event::kUnblocked, State::kTrackPath, OrderPhase::kToPick, Effect::kRestore);
  EXPECT_FALSE(m.suspended_state().has_value());
}

TEST(TaskStateMachine, CancelOnlyBeforeTheLift) {
  {
    TaskStateMachine m = machine_in(State::kSearchPallet);
    expect(m, Event::kCancel, State::kGoHome, OrderPhase::kNone, Effect::kCancelOrder);
  }
  {
    TaskStateMachine m = machine_in(State::kWaiting);  // waiting on the way to the pick
    expect(m, Event::kCancel, State::kGoHome, OrderPhase::kNone, Effect::kCancelOrder);
  }
  for (State s : {State::kPickPallet, State::kDropPallet, State::kIdle}) {
    TaskStateMachine m = machine_in(s);
    EXPECT_FALSE(m.handle(Event::kCancel).accepted) << to_string(s);
  }
  TaskStateMachine carrying = machine_in(State::kDropPallet);
  ASSERT_TRUE(carrying.handle(Event::kPause).accepted);
  ASSERT_TRUE(carrying.handle(Event::kResume).accepted);
  // TRACK_PATH to the drop: the pallet is on the forks, cancel is refused.
  TaskStateMachine to_drop = machine_in(State::kPickPallet);
  ASSERT_TRUE(to_drop.handle(Event::kPickDone).accepted);
  EXPECT_FALSE(to_drop.handle(Event::kCancel).accepted);
}

TEST(TaskStateMachine, FaultFromAnywhereAndReset) {
  for (State s : kAllStates) {
    if (s == State::kError) continue;
    TaskStateMachine m = machine_in(s);
    const Transition tr = m.handle(Event::kFault, "wheel stalled");
    ASSERT_TRUE(tr.accepted) << to_string(s);
    EXPECT_EQ(m.state(), State::kError);
    EXPECT_EQ(m.error_reason(), "wheel stalled");
    EXPECT_EQ(tr.effect, Effect::kFail);
    EXPECT_FALSE(m.handle(Event::kOrder).accepted);
    expect(m, Event::kReset, State::kIdle, OrderPhase::kNone, Effect::kClear);
    EXPECT_TRUE(m.error_reason().empty());
  }
}

TEST(TaskStateMachine, PickFailureSearchesAgainGivingUpGoesHomeDropFailureIsAnError) {
  TaskStateMachine m = machine_in(State::kPickPallet);
  expect(m, Event::kPickFailed, State::kSearchPallet, OrderPhase::kSearching, Effect::kStartSearch);
  TaskStateMachine g = machine_in(State::kPickPallet);
  expect(g, Event::kPickGaveUp, State::kGoHome, OrderPhase::kNone, Effect::kAbandonPick);
  TaskStateMachine d = machine_in(State::kDropPallet);
  expect(d, Event::kDropFailed, State::kError, OrderPhase::kNone, Effect::kFail);
}

TEST(TaskStateMachine, TableIsDeterministicAndEveryStateReachable) {
  // No two rows may match the same (state, phase, event): the table decides, not the row order.
  std::set<std::tuple<State, int, Event>> keys;
  for (const TransitionRow& row : transition_table()) {
    const int phase = row.any_phase ? -1 : static_cast<int>(row.phase);
    EXPECT_TRUE(keys.insert({row.from, phase, row.event}).second) << to_string(row.from) << " " << to_string(row.event);
    if (row.any_phase) {
      for (const TransitionRow& other : transition_table()) {
        if (&other != &row && other.from == row.from && other.event == row.event) {
          ADD_FAILURE() << "an any-phase row shadows another: " << to_string(row.from) << " " << to_string(row.event);
        }
      }
    }
  }
  // Walk the table from IDLE (restore rows lead back, so they add no new state).
  std::set<State> seen{State::kIdle};
  bool grew = true;
  while (grew) {
    grew = false;
    for (const TransitionRow& row : transition_table()) {
      if (seen.count(row.from) && !row.restore && seen.insert(row.to).second) grew = true;
    }
  }
  seen.insert(State::kError);  // by kFault, outside the table
  for (State s : kAllStates) EXPECT_TRUE(seen.count(s)) << to_string(s) << " unreachable";
  // Every state but ERROR has a way out.
  for (State s : kAllStates) {
    bool out = s == State::kError;
    for (const TransitionRow& row : transition_table())
      out = out || (row.from == s && row.to != s) || (row.from == s && row.restore);
    EXPECT_TRUE(out) << to_string(s);
  }
}

TEST(TaskStateMachine, RejectedEventsSayWhy) {
  TaskStateMachine m;
  const Transition tr = m.handle(Event::kPalletFound);
  EXPECT_FALSE(tr.accepted);
  EXPECT_EQ(tr.reason, "pallet_found not accepted in IDLE");
  EXPECT_EQ(m.state(), State::kIdle);
}

}  // namespace
}  // namespace fleet::task
