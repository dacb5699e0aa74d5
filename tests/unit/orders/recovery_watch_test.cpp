#include "orders/recovery_watch.hpp"

#include <gtest/gtest.h>

#include <string>

namespace fleet::orders {
namespace {

/// A book with order 1 (A1 -> A2) assigned to fl1 and order 2 (A3 -> A2) assigned to fl2, and a
/// ledger with a pallet on A1 and one on A3.
struct Yard {
  OrderBook book;
  AreaLedger ledger{{{"A1", {}}, {"A2", {}}, {"A3", {}}}};

  Yard() {
    for (const auto& [pick, robot] : {std::pair{"A1", "fl1"}, std::pair{"A3", "fl2"}}) {
      Order draft;
      draft.pick_area = pick;
      draft.drop_area = "A2";
      const std::int64_t id = book.create(draft, 0.0).id;
      EXPECT_EQ(book.assign(id, robot, 0.0), TransitionResult::kApplied);
    }
    ledger.record({1, "pallet", {}, "A1", ""});
    ledger.record({2, "pallet", {}, "A3", ""});
  }

  /// Order `id` accepted and past the lift: its robot carries its pallet.
  void lifted(std::int64_t id, int load) {
    ASSERT_EQ(book.transition(id, OrderStatus::kActive, 1.0), TransitionResult::kApplied);
    ASSERT_EQ(book.set_phase(id, OrderPhase::kToDrop, 1.0), TransitionResult::kApplied);
    ledger.record({load, "pallet", {}, "", book.find(id)->robot_id});
  }
};

TEST(RecoveryWatch, AnUnacknowledgedAssignmentIsSentAgainUpToTheLimitThenRequeued) {
  Yard yard;
  RecoveryWatch watch;
  watch.assigned(1);
  watch.sent(1, 10.0);
  EXPECT_TRUE(watch.check_acknowledgements(11.0, 2.0, 2, yard.book).empty()) << "within the timeout";
  auto steps = watch.check_acknowledgements(12.5, 2.0, 2, yard.book);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].action, Recovery::kResend);
  EXPECT_EQ(steps[0].robot_id, "fl1");
  EXPECT_EQ(steps[0].resends, 1);
  EXPECT_TRUE(watch.check_acknowledgements(13.0, 2.0, 2, yard.book).empty()) << "the wait starts again at a resend";
  steps = watch.check_acknowledgements(15.0, 2.0, 2, yard.book);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].resends, 2);
  steps = watch.check_acknowledgements(17.5, 2.0, 2, yard.book);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].action, Recovery::kRequeue);
  EXPECT_FALSE(watch.awaits_acknowledgement(1));
  EXPECT_TRUE(watch.check_acknowledgements(30.0, 2.0, 2, yard.book).empty()) << "a re-queued order is not watched";
}

TEST(RecoveryWatch, AReassignedOrderCountsItsResendsAfresh) {
  Yard yard;
  RecoveryWatch watch;
  watch.assigned(1);
  watch.sent(1, 0.0);
  ASSERT_EQ(watch.check_acknowledgements(3.0, 2.0, 1, yard.book).at(0).action, Recovery::kResend);
  watch.assigned(1);
  watch.sent(1, 3.0);
  const auto steps = watch.check_acknowledgements(6.0, 2.0, 1, yard.book);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].action, Recovery::kResend) << "not re-queued: the new assignment was never sent again";
}

TEST(RecoveryWatch, AnAnsweredOrMovedOnOrderIsNoLongerAwaited) {
  Yard yard;
  RecoveryWatch watch;
  watch.sent(1, 0.0);
  watch.sent(2, 0.0);
  watch.settled(1);
  EXPECT_FALSE(watch.awaits_acknowledgement(1));
  ASSERT_EQ(yard.book.transition(2, OrderStatus::kActive, 1.0), TransitionResult::kApplied);
  EXPECT_TRUE(watch.check_acknowledgements(5.0, 2.0, 3, yard.book).empty()) << "order 2 was accepted meanwhile";
  EXPECT_FALSE(watch.awaits_acknowledgement(2));
}

TEST(RecoveryWatch, AnOrderWaitsForItsLostRobotWithinTheLimitThenFailsOrIsRequeued) {
  Yard yard;
  yard.lifted(1, 1);  // fl1 carries order 1's pallet; fl2 never lifted order 2's
  RecoveryWatch watch;
  watch.wait_for_lost_robot(1, 100.0);
  watch.wait_for_lost_robot(2, 100.0);
  EXPECT_TRUE(watch.check_waiting(150.0, 60.0, yard.book, yard.ledger).empty());
  const auto steps = watch.check_waiting(161.0, 60.0, yard.book, yard.ledger);
  ASSERT_EQ(steps.size(), 2u);
  EXPECT_EQ(steps[0].order_id, 1);
  EXPECT_EQ(steps[0].robot_id, "fl1");
  EXPECT_EQ(steps[0].action, Recovery::kFailReturnLoad) << "the pallet is on the lost robot";
  EXPECT_EQ(steps[1].action, Recovery::kRequeue) << "the pallet still stands at the pick";
  EXPECT_FALSE(watch.waits_for_lost_robot(1));
  EXPECT_TRUE(watch.check_waiting(500.0, 60.0, yard.book, yard.ledger).empty());
}

TEST(RecoveryWatch, AnOrderThatEndedWhileItsRobotWasLostIsDroppedSilently) {
  Yard yard;
  RecoveryWatch watch;
  watch.wait_for_lost_robot(1, 0.0);
  ASSERT_EQ(yard.book.transition(1, OrderStatus::kCancelled, 1.0), TransitionResult::kApplied);
  EXPECT_TRUE(watch.check_waiting(1.0, 60.0, yard.book, yard.ledger).empty());
  EXPECT_FALSE(watch.waits_for_lost_robot(1));
}

TEST(RecoveryWatch, ARobotBackWithItsLoadKeepsItsOrder) {
  Yard yard;
  yard.lifted(1, 1);
  RecoveryWatch watch;
  watch.wait_for_lost_robot(1, 0.0);
  watch.wait_for_lost_robot(2, 0.0);
  const auto steps = watch.robot_back({"fl1", 1, true}, yard.book, yard.ledger);
  ASSERT_EQ(steps.size(), 1u) << "only fl1's order is decided";
  EXPECT_EQ(steps[0].action, Recovery::kKeep);
  EXPECT_FALSE(steps[0].withdraw);
  EXPECT_FALSE(watch.waits_for_lost_robot(1));
  EXPECT_TRUE(watch.waits_for_lost_robot(2));
}

TEST(RecoveryWatch, ARestartedRobotRunningTheOrderAgainIsToldToDropIt) {
  Yard yard;
  yard.lifted(1, 1);
  RecoveryWatch watch;
  watch.wait_for_lost_robot(1, 0.0);
  // Its forks are empty while the ledger has the pallet on them: it restarted and read the
  // latched assignment.
  const auto steps = watch.robot_back({"fl1", 1, false}, yard.book, yard.ledger);
  ASSERT_EQ(steps.size(), 1u);
  EXPECT_EQ(steps[0].action, Recovery::kFailReturnLoad);
  EXPECT_TRUE(steps[0].withdraw);
}

TEST(RecoveryWatch, AHandedBackOrderWaitsForNobody) {
  Yard yard;
  RecoveryWatch watch;
  watch.wait_for_lost_robot(1, 0.0);
  watch.handed_back(1);
  EXPECT_FALSE(watch.waits_for_lost_robot(1));
  EXPECT_TRUE(watch.robot_back({"fl1", 1, true}, yard.book, yard.ledger).empty());
}

}  // namespace
}  // namespace fleet::orders
