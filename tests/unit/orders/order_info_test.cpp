#include "orders/order_info.hpp"

#include <gtest/gtest.h>

#include "common/errors.hpp"
#include "orders/order_book.hpp"

using namespace fleet::orders;

namespace {
/// A pick order that went through dispatch, a re-queue and a second robot, with every field set.
Order travelled_order() {
  OrderBook book(40);
  Order draft;
  draft.request_id = "req-7";
  draft.kind = OrderKind::kPick;
  draft.pick_area = "RB1";
  draft.drop_area = "PS1";
  draft.lines = "RB1,A1,1\nRB3,A3,2\n";
  draft.fleet_id = "pickers";
  draft.robot_id = "pk2";
  draft.robot_requested = true;
  draft.priority = 4;
  draft.cause = "the pallet at PS1 is full";
  draft.caused_by = {12, 13};
  const std::int64_t id = book.create(draft, 10.0).id;
  book.assign(id, "pk2", 11.0);
  book.locate_last_event(id, 3.5, 4.25);
  book.set_phase(id, OrderPhase::kToPick, 12.0);
  book.requeue(id, 13.0, "robot pk2 lost");
  book.assign(id, "pk1", 14.0);
  book.set_phase(id, OrderPhase::kPicking, 15.0);
  book.transition(id, OrderStatus::kDone, 16.0);
  return *book.find(id);
}

void expect_same(const Order& a, const Order& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.request_id, b.request_id);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.pick_area, b.pick_area);
  EXPECT_EQ(a.drop_area, b.drop_area);
  EXPECT_EQ(a.lines, b.lines);
  EXPECT_EQ(a.fleet_id, b.fleet_id);
  EXPECT_EQ(a.robot_id, b.robot_id);
  EXPECT_EQ(a.robot_requested, b.robot_requested);
  EXPECT_EQ(a.priority, b.priority);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.phase, b.phase);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_EQ(a.update_id, b.update_id);
  EXPECT_EQ(a.created_sim, b.created_sim);
  EXPECT_EQ(a.updated_sim, b.updated_sim);
  EXPECT_EQ(a.assigned_sim, b.assigned_sim);
  EXPECT_EQ(a.finished_sim, b.finished_sim);
  EXPECT_EQ(a.cause, b.cause);
  EXPECT_EQ(a.caused_by, b.caused_by);
  ASSERT_EQ(a.history.size(), b.history.size());
  for (std::size_t i = 0; i < a.history.size(); ++i) {
    EXPECT_EQ(a.history[i].sim_time, b.history[i].sim_time) << i;
    EXPECT_EQ(a.history[i].status, b.history[i].status) << i;
    EXPECT_EQ(a.history[i].phase, b.history[i].phase) << i;
    EXPECT_EQ(a.history[i].robot_id, b.history[i].robot_id) << i;
    EXPECT_EQ(a.history[i].reason, b.history[i].reason) << i;
    EXPECT_EQ(a.history[i].robot_x, b.history[i].robot_x) << i;
    EXPECT_EQ(a.history[i].robot_y, b.history[i].robot_y) << i;
  }
}
}  // namespace

TEST(OrderInfo, CarriesEveryFieldAnOrderIsRebuiltFrom) {
  const Order order = travelled_order();
  ASSERT_EQ(order.status, OrderStatus::kDone);
  ASSERT_GT(order.update_id, 1u) << "the re-queue and second assignment raised it";
  ASSERT_GT(order.history.size(), 5u);
  expect_same(order_of(info_of(order)), order);
}

TEST(OrderInfo, AQueuedOrderWithoutPhaseComesBackQueued) {
  OrderBook book(1);
  Order draft;
  draft.drop_area = "H3";
  draft.kind = OrderKind::kMove;
  const Order queued = book.create(draft, 2.0);
  const Order back = order_of(info_of(queued));
  EXPECT_EQ(back.status, OrderStatus::kQueued);
  EXPECT_EQ(back.phase, OrderPhase::kNone);
  EXPECT_EQ(back.kind, OrderKind::kMove);
}

TEST(OrderInfo, AnUnknownNameIsRefusedNamingTheOrderAndField) {
  fleet::model::OrderInfo info = info_of(travelled_order());
  info.kind = "teleport";
  try {
    order_of(info);
    FAIL() << "accepted kind 'teleport'";
  } catch (const fleet::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("order 40: kind 'teleport'"), std::string::npos) << e.what();
  }
  info = info_of(travelled_order());
  info.history[1].state = "LOST";
  EXPECT_THROW(order_of(info), fleet::InputError);
}
