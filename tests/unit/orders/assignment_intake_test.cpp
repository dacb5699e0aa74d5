#include "orders/assignment_intake.hpp"

#include <gtest/gtest.h>

namespace fleet::orders {
namespace {

model::OrderAssignment assignment(std::int64_t order, std::uint32_t update, bool cancelled = false) {
  model::OrderAssignment a;
  a.order_id = order;
  a.robot_id = "fl1";
  a.update_id = update;
  a.cancelled = cancelled;
  return a;
}

model::OrderReport final_report(std::int64_t order, const std::string& status) {
  model::OrderReport r;
  r.order_id = order;
  r.status = status;
  return r;
}

TEST(AssignmentIntake, ANewOrderIsConsideredAndItsResendAcknowledgedAgain) {
  AssignmentIntake intake;
  EXPECT_EQ(intake.classify(assignment(7, 1), std::nullopt), IntakeStep::kConsider);
  const RunningOrder running{7, 1};
  EXPECT_EQ(intake.classify(assignment(7, 1), running), IntakeStep::kAcknowledgeAgain);
  EXPECT_EQ(intake.classify(assignment(7, 2), running), IntakeStep::kAcknowledgeAgain);
  // Another order while this one runs is considered (and refused as busy by refusal_of).
  EXPECT_EQ(intake.classify(assignment(8, 1), running), IntakeStep::kConsider);
}

TEST(AssignmentIntake, AWithdrawalEndsOnlyTheRunningOrderAndNotAnOlderUpdateOfIt) {
  AssignmentIntake intake;
  EXPECT_EQ(intake.classify(assignment(7, 3), std::nullopt), IntakeStep::kConsider);
  const RunningOrder running{7, 3};
  EXPECT_EQ(intake.classify(assignment(7, 2, true), running), IntakeStep::kIgnore);
  EXPECT_EQ(intake.classify(assignment(9, 4, true), running), IntakeStep::kIgnore);
  EXPECT_EQ(intake.classify(assignment(7, 4, true), running), IntakeStep::kWithdraw);
}

TEST(AssignmentIntake, ALateDuplicateOfAnEndedOrderRepeatsItsFinalReport) {
  AssignmentIntake intake;
  EXPECT_EQ(intake.classify(assignment(7, 1), std::nullopt), IntakeStep::kConsider);
  EXPECT_FALSE(intake.remember_end(final_report(7, "DONE")));
  // A restarted server offers the order again: the robot says how it ended.
  EXPECT_EQ(intake.classify(assignment(7, 1), std::nullopt), IntakeStep::kRepeatFinalReport);
  ASSERT_NE(intake.final_report(7), nullptr);
  EXPECT_EQ(intake.final_report(7)->status, "DONE");
  // A duplicate of an order it knows no end of is dropped; a newer update of it is new.
  EXPECT_EQ(intake.classify(assignment(8, 1), std::nullopt), IntakeStep::kConsider);
  EXPECT_EQ(intake.classify(assignment(8, 1), std::nullopt), IntakeStep::kIgnore);
  EXPECT_EQ(intake.classify(assignment(8, 2), std::nullopt), IntakeStep::kConsider);
}

TEST(AssignmentIntake, KeepsTheLastFinalReportsAndHandsBackTheOneThatDropsOut) {
  AssignmentIntake intake(2);
  EXPECT_FALSE(intake.remember_end(final_report(1, "DONE")));
  EXPECT_FALSE(intake.remember_end(final_report(2, "FAILED")));
  const auto dropped = intake.remember_end(final_report(3, "DONE"));
  ASSERT_TRUE(dropped);
  EXPECT_EQ(dropped->order_id, 1);
  EXPECT_EQ(intake.final_report(1), nullptr);
  EXPECT_EQ(intake.final_report(2)->status, "FAILED");
}

TEST(AssignmentIntake, ANewOrderIsRefusedForTheFirstReasonThatApplies) {
  NewOrderChecks checks;
  EXPECT_EQ(AssignmentIntake::refusal_of(checks), "");
  checks.paused = true;
  EXPECT_EQ(AssignmentIntake::refusal_of(checks), "paused by the operator");
  checks.robot_refusal = "a stacker does no pick orders";
  EXPECT_EQ(AssignmentIntake::refusal_of(checks), "a stacker does no pick orders");
  checks.busy_with = 12;
  EXPECT_EQ(AssignmentIntake::refusal_of(checks), "busy with order 12");
  checks.invalid = "unknown order kind 'fly'";
  EXPECT_EQ(AssignmentIntake::refusal_of(checks), "unknown order kind 'fly'");
}

}  // namespace
}  // namespace fleet::orders
