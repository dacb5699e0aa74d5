#include <gtest/gtest.h>

#include "monitor/collision_monitor.hpp"
#include "monitor/order_accounting.hpp"

using namespace fleet;
using namespace fleet::monitor;

TEST(CollisionMonitor, OverlapCountsOnceUntilSeparated) {
  CollisionMonitor m;
  const geometry::Footprint fp{0.25, 0.16};
  EXPECT_TRUE(m.update("a", {0, 0, 0}, fp, 1.00).empty());
  EXPECT_TRUE(m.update("b", {1, 0, 0}, fp, 1.00).empty());
  auto hits = m.update("b", {0.2, 0, 0}, fp, 1.05);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].robot_a, "b");
  EXPECT_EQ(hits[0].robot_b, "a");
  EXPECT_TRUE(m.update("a", {0.01, 0, 0}, fp, 1.08).empty());  // still in contact: the same collision
  EXPECT_TRUE(m.update("b", {0.5, 0, 0}, fp, 1.10).empty());   // separated
  EXPECT_TRUE(m.update("a", {0.01, 0, 0}, fp, 1.12).empty());
  EXPECT_EQ(m.update("b", {0.2, 0, 0}, fp, 1.15).size(), 1u);  // a second collision
  EXPECT_EQ(m.collisions().size(), 2u);
}

TEST(CollisionMonitor, TruthsFarApartInTimeAreNotCompared) {
  CollisionMonitor m(0.1);
  const geometry::Footprint fp{0.25, 0.16};
  m.update("a", {0, 0, 0}, fp, 1.0);
  EXPECT_TRUE(m.update("b", {0, 0, 0}, fp, 5.0).empty());
}

TEST(OrderAccounting, GapsAreLostOrders) {
  std::map<std::int64_t, model::OrderInfo> orders;
  auto add = [&](std::int64_t id, const char* state) {
    model::OrderInfo info;
    info.order_id = id;
    info.state = state;
    orders[id] = info;
  };
  add(3, "DONE");
  add(4, "FAILED");
  add(6, "ACTIVE");
  add(7, "CANCELLED");
  const OrderTally t = tally_orders(orders, 3);
  EXPECT_EQ(t.created, 5);
  EXPECT_EQ(t.done, 1);
  EXPECT_EQ(t.failed, 1);
  EXPECT_EQ(t.open, 1);
  EXPECT_EQ(t.cancelled, 1);
  EXPECT_EQ(t.lost, 1);  // order 5 vanished
  EXPECT_EQ(tally_orders(orders, 6).created, 2);
  EXPECT_EQ(tally_orders({}, 1).created, 0);
}
