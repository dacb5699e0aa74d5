#include <gtest/gtest.h>

#include "orders/order_book.hpp"

using namespace fleet::orders;

namespace {
Order draft(const std::string& from, const std::string& to, int priority = 0) {
  Order o;
  o.pick_area = from;
  o.drop_area = to;
  o.priority = priority;
  return o;
}
}  // namespace

TEST(OrderLifecycle, LegalTransitionsOnly) {
  using S = OrderStatus;
  EXPECT_TRUE(is_legal_transition(S::kQueued, S::kAssigned));
  EXPECT_TRUE(is_legal_transition(S::kAssigned, S::kActive));
  EXPECT_TRUE(is_legal_transition(S::kActive, S::kDone));
  EXPECT_TRUE(is_legal_transition(S::kActive, S::kQueued));
  EXPECT_FALSE(is_legal_transition(S::kQueued, S::kActive));
  EXPECT_FALSE(is_legal_transition(S::kQueued, S::kDone));
  for (S final_state : {S::kDone, S::kFailed, S::kCancelled}) {
    for (S any : {S::kQueued, S::kAssigned, S::kActive, S::kDone, S::kFailed, S::kCancelled}) {
      EXPECT_FALSE(is_legal_transition(final_state, any));
    }
  }
}

TEST(OrderLifecycle, NamesRoundTrip) {
  for (auto s : {OrderStatus::kQueued, OrderStatus::kAssigned, OrderStatus::kActive, OrderStatus::kDone,
                 OrderStatus::kFailed, OrderStatus::kCancelled}) {
    EXPECT_EQ(parse_status(to_string(s)), s);
  }
  EXPECT_EQ(parse_phase("PICKING"), OrderPhase::kPicking);
  EXPECT_FALSE(parse_phase("FLYING").has_value());
}

TEST(OrderBook, IdsIncreaseAndAreNeverReused) {
  OrderBook book(41);
  EXPECT_EQ(book.create(draft("A1", "A2"), 0.0).id, 41);
  EXPECT_EQ(book.create(draft("A1", "A2"), 0.0).id, 42);
  Order old = *book.find(41);
  old.id = 100;
  book.restore(old);
  EXPECT_EQ(book.create(draft("A1", "A2"), 0.0).id, 101);
}

TEST(OrderBook, FullRunAndRefusedIllegalStep) {
  OrderBook book;
  const auto id = book.create(draft("A1", "A2"), 1.0).id;
  EXPECT_EQ(book.set_phase(id, OrderPhase::kToPick, 2.0), TransitionResult::kIllegal);  // not yet assigned
  EXPECT_EQ(book.assign(id, "fl1", 2.0), TransitionResult::kApplied);
  EXPECT_EQ(book.find(id)->update_id, 1u);
  EXPECT_EQ(book.set_phase(id, OrderPhase::kToPick, 3.0), TransitionResult::kApplied);
  EXPECT_EQ(book.open_order_of("fl1")->id, id);
  EXPECT_EQ(book.transition(id, OrderStatus::kDone, 9.0), TransitionResult::kApplied);
  EXPECT_EQ(book.transition(id, OrderStatus::kCancelled, 10.0), TransitionResult::kIllegal);
  EXPECT_EQ(book.find(id)->status, OrderStatus::kDone);
  EXPECT_EQ(book.transition(999, OrderStatus::kDone, 10.0), TransitionResult::kUnknownOrder);
}

TEST(OrderBook, RequeueClearsRobotAndPhase) {
  OrderBook book;
  const auto id = book.create(draft("A1", "A2"), 0.0).id;
  book.assign(id, "fl2", 1.0);
  book.set_phase(id, OrderPhase::kPicking, 2.0);
  EXPECT_EQ(book.requeue(id, 3.0, "robot fl2 lost"), TransitionResult::kApplied);
  EXPECT_EQ(book.find(id)->status, OrderStatus::kQueued);
  EXPECT_TRUE(book.find(id)->robot_id.empty());
  EXPECT_EQ(book.find(id)->reason, "robot fl2 lost");
  EXPECT_EQ(book.open_order_of("fl2"), nullptr);
}

// Regression: a DONE order showed phase DROPPING, and the reason of its re-queueing stuck to it
// through its second assignment to the end.
TEST(OrderBook, ADoneOrderIsInNoPhaseAndCarriesOnlyTheReasonOfItsCurrentState) {
  OrderBook book;
  const auto id = book.create(draft("A1", "A2"), 0.0).id;
  book.assign(id, "fl2", 1.0);
  book.requeue(id, 2.0, "robot fl2 lost");
  book.assign(id, "fl3", 3.0);
  EXPECT_EQ(book.find(id)->reason, "");
  book.set_phase(id, OrderPhase::kDropping, 4.0);
  EXPECT_EQ(book.transition(id, OrderStatus::kDone, 5.0), TransitionResult::kApplied);
  const Order& done = *book.find(id);
  EXPECT_EQ(done.phase, OrderPhase::kNone);
  EXPECT_EQ(done.reason, "");
  EXPECT_EQ(done.history.back().phase, OrderPhase::kDropping) << "the history says where it ended";
  EXPECT_EQ(done.history[2].reason, "robot fl2 lost") << "and keeps every reason";
}

TEST(OrderBook, QueueIsByPriorityThenAge) {
  OrderBook book;
  const auto low = book.create(draft("A1", "A2", 0), 0.0).id;
  const auto high = book.create(draft("A1", "A2", 5), 1.0).id;
  const auto low2 = book.create(draft("A1", "A2", 0), 2.0).id;
  const auto q = book.queue();
  ASSERT_EQ(q.size(), 3u);
  EXPECT_EQ(q[0]->id, high);
  EXPECT_EQ(q[1]->id, low);
  EXPECT_EQ(q[2]->id, low2);
}
