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
  EXPECT_TRUE(is_legal_transition(S::Queued, S::Assigned));
  EXPECT_TRUE(is_legal_transition(S::Assigned, S::Active));
  EXPECT_TRUE(is_legal_transition(S::Active, S::Done));
  EXPECT_TRUE(is_legal_transition(S::Active, S::Queued));
  EXPECT_FALSE(is_legal_transition(S::Queued, S::Active));
  EXPECT_FALSE(is_legal_transition(S::Queued, S::Done));
  for (S final_state : {S::Done, S::Failed, S::Cancelled}) {
    for (S any : {S::Queued, S::Assigned, S::Active, S::Done, S::Failed, S::Cancelled}) {
      EXPECT_FALSE(is_legal_transition(final_state, any));
    }
  }
}

TEST(OrderLifecycle, NamesRoundTrip) {
  for (auto s : {OrderStatus::Queued, OrderStatus::Assigned, OrderStatus::Active, OrderStatus::Done,
                 OrderStatus::Failed, OrderStatus::Cancelled}) {
    EXPECT_EQ(parse_status(to_string(s)), s);
  }
  EXPECT_EQ(parse_phase("PICKING"), OrderPhase::Picking);
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
  EXPECT_EQ(book.set_phase(id, OrderPhase::ToPick, 2.0), TransitionResult::Illegal);  // not yet assigned
  EXPECT_EQ(book.assign(id, "fl1", 2.0), TransitionResult::Applied);
  EXPECT_EQ(book.find(id)->update_id, 1u);
  EXPECT_EQ(book.set_phase(id, OrderPhase::ToPick, 3.0), TransitionResult::Applied);
  EXPECT_EQ(book.open_order_of("fl1")->id, id);
  EXPECT_EQ(book.transition(id, OrderStatus::Done, 9.0), TransitionResult::Applied);
  EXPECT_EQ(book.transition(id, OrderStatus::Cancelled, 10.0), TransitionResult::Illegal);
  EXPECT_EQ(book.find(id)->status, OrderStatus::Done);
  EXPECT_EQ(book.transition(999, OrderStatus::Done, 10.0), TransitionResult::UnknownOrder);
}

TEST(OrderBook, RequeueClearsRobotAndPhase) {
  OrderBook book;
  const auto id = book.create(draft("A1", "A2"), 0.0).id;
  book.assign(id, "fl2", 1.0);
  book.set_phase(id, OrderPhase::Picking, 2.0);
  EXPECT_EQ(book.requeue(id, 3.0, "robot fl2 lost"), TransitionResult::Applied);
  EXPECT_EQ(book.find(id)->status, OrderStatus::Queued);
  EXPECT_TRUE(book.find(id)->robot_id.empty());
  EXPECT_EQ(book.find(id)->reason, "robot fl2 lost");
  EXPECT_EQ(book.open_order_of("fl2"), nullptr);
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
