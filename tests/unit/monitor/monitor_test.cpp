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

TEST(OrderStats, CountsRatesTimesAndUtilisation) {
  std::map<std::int64_t, model::OrderInfo> orders;
  auto order = [&](std::int64_t id, const char* state, double created, double ended,
                   std::vector<model::OrderEvent> history) {
    model::OrderInfo o;
    o.order_id = id;
    o.state = state;
    o.created_sim = created;
    o.updated_sim = ended;
    o.history = std::move(history);
    orders[id] = o;
  };
  // fl1 busy 100..160 (done), fl2 busy 200..250 then re-queued, then fl1 250..300 and still active.
  order(1, "DONE", 100, 160, {{100, "QUEUED", "", "", "", 0, 0}, {100, "ASSIGNED", "", "fl1", "", 0, 0},
                               {110, "ACTIVE", "TO_PICK", "fl1", "", 0, 0}, {160, "DONE", "DROPPING", "fl1", "", 0, 0}});
  order(2, "ACTIVE", 200, 250, {{200, "QUEUED", "", "", "", 0, 0}, {200, "ASSIGNED", "", "fl2", "", 0, 0},
                                 {250, "QUEUED", "", "", "robot fl2 lost", 0, 0}, {250, "ASSIGNED", "", "fl1", "", 0, 0}});
  const OrderStats s = order_stats(orders, 300);
  EXPECT_EQ(s.by_state.at("DONE"), 1);
  EXPECT_EQ(s.by_state.at("ACTIVE"), 1);
  EXPECT_EQ(s.by_state.at("QUEUED"), 0);
  EXPECT_DOUBLE_EQ(s.span_s, 200.0);
  EXPECT_DOUBLE_EQ(s.done_per_hour, 18.0);
  EXPECT_DOUBLE_EQ(s.order_time_mean_s, 60.0);
  EXPECT_DOUBLE_EQ(s.order_time_p95_s, 60.0);
  EXPECT_DOUBLE_EQ(s.utilisation.at("fl1"), (60.0 + 50.0) / 200.0);
  EXPECT_DOUBLE_EQ(s.utilisation.at("fl2"), 50.0 / 200.0);
}

TEST(OrderStats, PercentileByNearestRank) {
  EXPECT_DOUBLE_EQ(percentile({}, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(percentile({3, 1, 2}, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 0.95), 10.0);
  EXPECT_DOUBLE_EQ(percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 0.0), 1.0);
}
