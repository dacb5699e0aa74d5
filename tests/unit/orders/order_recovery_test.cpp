#include "orders/order_recovery.hpp"

#include <gtest/gtest.h>

using namespace fleet::orders;

namespace {
constexpr OrderPhase kAllPhases[] = {OrderPhase::kNone,    OrderPhase::kToPick, OrderPhase::kSearching,
                                     OrderPhase::kPicking, OrderPhase::kToDrop, OrderPhase::kDropping};
}  // namespace

TEST(OrderRecovery, LostOnTheWayToThePickIsRequeued) {
  EXPECT_EQ(when_robot_lost({OrderPhase::kNone, false}), Recovery::kRequeue);
  EXPECT_EQ(when_robot_lost({OrderPhase::kToPick, false}), Recovery::kRequeue);
}

TEST(OrderRecovery, LostWithTheLoadOnItsForksWaitsForTheRobot) {
  for (OrderPhase phase : kAllPhases) EXPECT_EQ(when_robot_lost({phase, true}), Recovery::kWait) << to_string(phase);
}

TEST(OrderRecovery, LostAtThePickPlaceWaitsForTheRobot) {
  EXPECT_EQ(when_robot_lost({OrderPhase::kSearching, false}), Recovery::kWait);
  EXPECT_EQ(when_robot_lost({OrderPhase::kPicking, false}), Recovery::kWait);
}

TEST(OrderRecovery, APickerLostWithTheTourBoxesOnItsTrayWaitsForIt) {
  for (OrderPhase phase : {OrderPhase::kToPick, OrderPhase::kToDrop, OrderPhase::kDropping}) {
    EXPECT_EQ(when_robot_lost({phase, false, true}), Recovery::kWait) << to_string(phase);
  }
  Order tour;
  tour.kind = OrderKind::kPick;
  const auto event = [&](OrderStatus status, OrderPhase phase) {
    tour.history.push_back({0.0, status, phase, "pk3", "", 0.0, 0.0});
  };
  event(OrderStatus::kQueued, OrderPhase::kNone);
  event(OrderStatus::kAssigned, OrderPhase::kNone);
  event(OrderStatus::kActive, OrderPhase::kToPick);
  EXPECT_FALSE(boxes_aboard(tour)) << "nothing picked yet";
  event(OrderStatus::kActive, OrderPhase::kPicking);
  event(OrderStatus::kActive, OrderPhase::kToPick);  // to the tour's second place
  EXPECT_TRUE(boxes_aboard(tour));
  event(OrderStatus::kActive, OrderPhase::kToDrop);
  EXPECT_TRUE(boxes_aboard(tour));
  event(OrderStatus::kQueued, OrderPhase::kNone);  // given up on: another picker starts afresh
  event(OrderStatus::kAssigned, OrderPhase::kNone);
  event(OrderStatus::kActive, OrderPhase::kToPick);
  EXPECT_FALSE(boxes_aboard(tour));
  Order transport = tour;
  transport.kind = OrderKind::kTransport;
  transport.history.push_back({0.0, OrderStatus::kActive, OrderPhase::kPicking, "fk1", "", 0.0, 0.0});
  EXPECT_FALSE(boxes_aboard(transport)) << "a transport's load is on the forks, reported as such";
}

TEST(OrderRecovery, GivingUpBeforeTheLiftRequeues) {
  EXPECT_EQ(when_giving_up(false), Recovery::kRequeue);
}

TEST(OrderRecovery, GivingUpWithTheLoadFailsAndReturnsIt) {
  EXPECT_EQ(when_giving_up(true), Recovery::kFailReturnLoad);
}

TEST(OrderRecovery, AWaitingOrderThatEndedIsForgotten) {
  EXPECT_EQ(when_waiting({.order_open = false, .waited_s = 100.0, .wait_limit_s = 30.0, .robot_carries_load = true}),
            Recovery::kForget);
}

TEST(OrderRecovery, AWaitingOrderWaitsUpToItsLimit) {
  EXPECT_EQ(when_waiting({.order_open = true, .waited_s = 29.9, .wait_limit_s = 30.0}), Recovery::kWait);
  EXPECT_EQ(when_waiting({.order_open = true, .waited_s = 30.0, .wait_limit_s = 30.0}), Recovery::kWait);
}

TEST(OrderRecovery, ARobotNotBackInTimeIsGivenUpOn) {
  EXPECT_EQ(when_waiting({.order_open = true, .waited_s = 30.1, .wait_limit_s = 30.0, .robot_carries_load = false}),
            Recovery::kRequeue);
  EXPECT_EQ(when_waiting({.order_open = true, .waited_s = 30.1, .wait_limit_s = 30.0, .robot_carries_load = true}),
            Recovery::kFailReturnLoad);
}

TEST(OrderRecovery, BackWithTheLoadOnItsForksResumes) {
  const auto decision = when_robot_back({.order_open = true,
                                         .reports_this_order = true,
                                         .robot_carries_load = true,
                                         .reports_carrying = true,
                                         .phase = OrderPhase::kToDrop});
  EXPECT_EQ(decision.action, Recovery::kKeep);
  EXPECT_FALSE(decision.withdraw);
}

TEST(OrderRecovery, BackStillAtThePickResumes) {
  const auto decision = when_robot_back({.order_open = true,
                                         .reports_this_order = true,
                                         .robot_carries_load = false,
                                         .reports_carrying = false,
                                         .phase = OrderPhase::kSearching});
  EXPECT_EQ(decision.action, Recovery::kKeep);
}

TEST(OrderRecovery, BackAfterPuttingTheLoadDownResumes) {
  // Frozen as it put the load down at the drop: empty forks, the DONE report follows.
  const auto decision = when_robot_back({.order_open = true,
                                         .reports_this_order = true,
                                         .robot_carries_load = true,
                                         .reports_carrying = false,
                                         .phase = OrderPhase::kDropping});
  EXPECT_EQ(decision.action, Recovery::kKeep);
}

TEST(OrderRecovery, BackRestartedWithEmptyForksFailsReturnsTheLoadAndWithdraws) {
  const auto decision = when_robot_back({.order_open = true,
                                         .reports_this_order = true,
                                         .robot_carries_load = true,
                                         .reports_carrying = false,
                                         .phase = OrderPhase::kToDrop});
  EXPECT_EQ(decision.action, Recovery::kFailReturnLoad);
  EXPECT_TRUE(decision.withdraw);
}

TEST(OrderRecovery, BackNamingNoOrderBeforeTheLiftIsRequeuedWithoutWithdrawal) {
  const auto decision = when_robot_back({.order_open = true,
                                         .reports_this_order = false,
                                         .robot_carries_load = false,
                                         .reports_carrying = false,
                                         .phase = OrderPhase::kPicking});
  EXPECT_EQ(decision.action, Recovery::kRequeue);
  EXPECT_FALSE(decision.withdraw);
}

TEST(OrderRecovery, BackToAnOrderThatEndedForgetsIt) {
  const auto decision = when_robot_back({.order_open = false, .reports_this_order = true});
  EXPECT_EQ(decision.action, Recovery::kForget);
  EXPECT_FALSE(decision.withdraw);
}

TEST(OrderRecovery, ReappearingWithAnEndedOrderWithdrawsIt) {
  EXPECT_EQ(when_robot_reappears({.order_final = true, .order_is_robots = true}), Recovery::kWithdraw);
}

TEST(OrderRecovery, ReappearingWithAnOrderGivenToAnotherWithdrawsIt) {
  EXPECT_EQ(when_robot_reappears({.order_final = false, .order_is_robots = false}), Recovery::kWithdraw);
}

TEST(OrderRecovery, ReappearingWithItsOwnOpenOrderKeepsIt) {
  EXPECT_EQ(when_robot_reappears({.order_final = false, .order_is_robots = true}), Recovery::kKeep);
}

TEST(OrderRecovery, AnUnacknowledgedAssignmentIsResentUpToTheLimitThenRequeued) {
  AcknowledgementFacts facts{
      .still_assigned = true, .waited_s = 1.0, .timeout_s = 2.0, .resends = 0, .resend_limit = 2};
  EXPECT_EQ(when_unacknowledged(facts), Recovery::kWait);
  facts.waited_s = 2.0;
  EXPECT_EQ(when_unacknowledged(facts), Recovery::kResend);
  facts.resends = 2;
  EXPECT_EQ(when_unacknowledged(facts), Recovery::kRequeue);
  facts.still_assigned = false;
  EXPECT_EQ(when_unacknowledged(facts), Recovery::kForget);
}

TEST(OrderRecovery, ARestoredOrdersRobotIsLostAfterTheRestartGrace) {
  EXPECT_DOUBLE_EQ(restart_grace_s(0.5), 3.0);
  EXPECT_DOUBLE_EQ(restart_grace_s(2.0), 6.0);
  EXPECT_TRUE(restored_robot_carried_load(OrderPhase::kToDrop));
  EXPECT_TRUE(restored_robot_carried_load(OrderPhase::kDropping));
  EXPECT_FALSE(restored_robot_carried_load(OrderPhase::kPicking));
  EXPECT_FALSE(restored_robot_carried_load(OrderPhase::kToPick));
}

namespace {
/// A report from a robot the order was taken from, which lifted the load on its way.
ReportFacts lifted_by_former_robot() {
  return {.order_status = OrderStatus::kQueued,
          .order_phase = OrderPhase::kNone,
          .from_order_robot = false,
          .current_update = false,
          .reported = "TO_DROP",
          .reports_carrying = true,
          .reporter_registered = true};
}
}  // namespace

TEST(OrderRecovery, AFormerRobotThatLiftedTheLoadIsHandedTheOrderBack) {
  EXPECT_EQ(judge_report(lifted_by_former_robot()), ReportVerdict::kHandBack);
  ReportFacts reassigned = lifted_by_former_robot();
  reassigned.order_status = OrderStatus::kActive;
  reassigned.order_phase = OrderPhase::kToPick;
  EXPECT_EQ(judge_report(reassigned), ReportVerdict::kHandBack);
}

TEST(OrderRecovery, NoHandBackOnceTheNewRobotPicks) {
  for (OrderPhase phase : {OrderPhase::kPicking, OrderPhase::kToDrop, OrderPhase::kDropping}) {
    ReportFacts facts = lifted_by_former_robot();
    facts.order_status = OrderStatus::kActive;
    facts.order_phase = phase;
    EXPECT_EQ(judge_report(facts), ReportVerdict::kStale) << to_string(phase);
  }
}

TEST(OrderRecovery, NoHandBackWithoutTheLoadLifted) {
  ReportFacts empty = lifted_by_former_robot();
  empty.reports_carrying = false;
  EXPECT_EQ(judge_report(empty), ReportVerdict::kStale);
  ReportFacts searching = lifted_by_former_robot();
  searching.reported = "SEARCHING";
  EXPECT_EQ(judge_report(searching), ReportVerdict::kStale);
}

TEST(OrderRecovery, NoHandBackToAnUnregisteredRobotOrOfAnEndedOrder) {
  ReportFacts unregistered = lifted_by_former_robot();
  unregistered.reporter_registered = false;
  EXPECT_EQ(judge_report(unregistered), ReportVerdict::kStale);
  ReportFacts ended = lifted_by_former_robot();
  ended.order_status = OrderStatus::kCancelled;
  EXPECT_EQ(judge_report(ended), ReportVerdict::kStale);
}

TEST(OrderRecovery, AnOldUpdateFromTheOrdersRobotIsStale) {
  ReportFacts facts = lifted_by_former_robot();
  facts.from_order_robot = true;
  facts.order_status = OrderStatus::kActive;
  EXPECT_EQ(judge_report(facts), ReportVerdict::kStale);
}

TEST(OrderRecovery, TheSameEndStateAgainIsARepeat) {
  EXPECT_EQ(judge_report({.order_status = OrderStatus::kDone, .reported = "DONE"}), ReportVerdict::kRepeated);
  EXPECT_EQ(judge_report({.order_status = OrderStatus::kFailed, .reported = "FAILED"}), ReportVerdict::kRepeated);
}

TEST(OrderRecovery, AReportOnAnEndedOrderWithdrawsIt) {
  EXPECT_EQ(judge_report({.order_status = OrderStatus::kFailed, .reported = "TO_PICK"}), ReportVerdict::kWithdraw);
  EXPECT_EQ(judge_report({.order_status = OrderStatus::kCancelled, .reported = "DONE"}), ReportVerdict::kWithdraw);
}

TEST(OrderRecovery, ACurrentReportOnAnOpenOrderApplies) {
  EXPECT_EQ(judge_report({.order_status = OrderStatus::kAssigned, .reported = "ACCEPTED"}), ReportVerdict::kApply);
  EXPECT_EQ(judge_report({.order_status = OrderStatus::kActive, .reported = "DONE"}), ReportVerdict::kApply);
}
