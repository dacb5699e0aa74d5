#include "orders/order_merge.hpp"

#include <gtest/gtest.h>

#include "orders/order_book.hpp"
#include "orders/server_term.hpp"

namespace fleet::orders {
namespace {

Order transport(const std::string& from, const std::string& to) {
  Order o;
  o.pick_area = from;
  o.drop_area = to;
  return o;
}

// The order both servers knew when they were cut off from each other: queued at t = 10.
Order known_before_the_cut() {
  OrderBook book(7);
  return book.create(transport("A1", "B1"), 10.0);
}

Order moved_on(Order order, const std::string& robot, OrderStatus to, double at) {
  order.robot_id = robot;
  for (OrderStatus s : {OrderStatus::kAssigned, OrderStatus::kActive, OrderStatus::kDone}) {
    if (static_cast<int>(order.status) >= static_cast<int>(s)) continue;
    order.status = s;
    order.history.push_back({at, s, OrderPhase::kNone, robot, "", 0.0, 0.0});
    at += 1.0;
    if (s == to) break;
  }
  return order;
}

TEST(OrderMerge, AnOrderCreatedOnTheOtherSideIsAdopted) {
  const Order theirs = known_before_the_cut();
  const MergeDecision d = merge_handed_over(nullptr, theirs);
  EXPECT_EQ(d.choice, MergeChoice::kAdopt);
  EXPECT_FALSE(d.ran_on_both_sides);
}

TEST(OrderMerge, TheSameVersionOnBothIsKept) {
  const Order own = known_before_the_cut();
  EXPECT_EQ(merge_handed_over(&own, own).choice, MergeChoice::kKeepOwn);
}

TEST(OrderMerge, AnOrderThatEndedOnTheOtherSideBeatsOneStillQueuedHere) {
  const Order own = known_before_the_cut();
  const Order theirs = moved_on(own, "fk1", OrderStatus::kDone, 20.0);
  const MergeDecision d = merge_handed_over(&own, theirs);
  EXPECT_EQ(d.choice, MergeChoice::kAdopt);
  EXPECT_FALSE(d.ran_on_both_sides) << "only one side gave it to a robot";
}

TEST(OrderMerge, TheActiveServersFurtherVersionStands) {
  const Order before = known_before_the_cut();
  const Order own = moved_on(before, "fk2", OrderStatus::kActive, 20.0);
  const MergeDecision d = merge_handed_over(&own, before);
  EXPECT_EQ(d.choice, MergeChoice::kKeepOwn);
  EXPECT_FALSE(d.ran_on_both_sides);
}

TEST(OrderMerge, GivenToARobotOnEachSideTheFurtherRunStandsAndTheRunTwiceIsNamed) {
  const Order before = known_before_the_cut();
  const Order own = moved_on(before, "fk2", OrderStatus::kAssigned, 20.0);
  const Order theirs = moved_on(before, "fk1", OrderStatus::kActive, 21.0);
  const MergeDecision d = merge_handed_over(&own, theirs);
  EXPECT_EQ(d.choice, MergeChoice::kAdopt);
  EXPECT_TRUE(d.ran_on_both_sides);
  // And the other way round: the active server's run is the further one.
  const MergeDecision back = merge_handed_over(&theirs, own);
  EXPECT_EQ(back.choice, MergeChoice::kKeepOwn);
  EXPECT_TRUE(back.ran_on_both_sides);
}

TEST(OrderMerge, OfTwoEndedVersionsTheActiveServersStandsAndTwoDonesAreNamed) {
  const Order before = known_before_the_cut();
  const Order own = moved_on(before, "fk2", OrderStatus::kDone, 20.0);
  const Order theirs = moved_on(before, "fk1", OrderStatus::kDone, 25.0);
  const MergeDecision d = merge_handed_over(&own, theirs);
  EXPECT_EQ(d.choice, MergeChoice::kKeepOwn);
  EXPECT_TRUE(d.ran_on_both_sides);
}

TEST(OrderMerge, TheServerThatTookOverAndTheOneCutOffHandOutIdsFromBlocksOfTheirOwn) {
  EXPECT_EQ(first_order_id(1), 1);
  EXPECT_EQ(first_order_id(2), kOrderIdsPerTerm + 1);
  EXPECT_EQ(first_order_id(0), 1);
  // A server cut off in term 1 goes on below the block of term 2, where the one that took over begins.
  OrderBook cut_off(first_order_id(1) + 500);
  OrderBook took_over(first_order_id(2));
  const Order draft = known_before_the_cut();
  EXPECT_LT(cut_off.create(draft, 0.0).id, took_over.create(draft, 0.0).id);
}

}  // namespace
}  // namespace fleet::orders
