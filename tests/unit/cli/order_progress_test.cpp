#include "cli/order_progress.hpp"

#include <gtest/gtest.h>

using namespace fleet::cli;
using fleet::model::OrderEvent;
using fleet::model::OrderInfo;

namespace {
/// An order created at `t0` with events at the given offsets.
OrderInfo order_with(std::int64_t id, double t0,
                     const std::vector<std::pair<double, std::pair<std::string, std::string>>>& events) {
  OrderInfo o;
  o.order_id = id;
  o.pick_area = "A1";
  o.drop_area = "A2";
  o.created_sim = t0;
  o.history.push_back({t0, "QUEUED", "", "", "", 0, 0});
  for (const auto& [dt, state_phase] : events) {
    o.history.push_back({t0 + dt, state_phase.first, state_phase.second, "fl1", "", 0, 0});
  }
  o.state = o.history.back().state;
  o.phase = o.history.back().phase;
  o.robot_id = "fl1";
  o.updated_sim = o.history.back().sim_time;
  return o;
}

OrderInfo done_order(std::int64_t id, double t0) {
  // Assigned at +10, TO_PICK at +11, TO_DROP at +31, DONE at +51.
  return order_with(
      id, t0, {{10, {"ASSIGNED", ""}}, {11, {"ACTIVE", "TO_PICK"}}, {31, {"ACTIVE", "TO_DROP"}}, {51, {"DONE", ""}}});
}
}  // namespace

TEST(DurationModel, MeansPerStageFromDoneOrders) {
  std::map<std::int64_t, OrderInfo> orders{{1, done_order(1, 100)}, {2, done_order(2, 200)}};
  const DurationModel model(orders);
  EXPECT_EQ(model.done_orders(), 2);
  EXPECT_DOUBLE_EQ(*model.mean_work(), 41.0);
  EXPECT_DOUBLE_EQ(*model.mean_to_done("TO_PICK"), 40.0);
  EXPECT_DOUBLE_EQ(*model.mean_to_done("TO_DROP"), 20.0);
  EXPECT_FALSE(model.mean_to_done("SEARCHING"));
}

TEST(Progress, UnknownUntilAnOrderIsDoneThenMeanMinusTimeInStage) {
  const OrderInfo active =
      order_with(3, 1000, {{5, {"ASSIGNED", ""}}, {6, {"ACTIVE", "TO_PICK"}}, {20, {"ACTIVE", "TO_DROP"}}});
  const DurationModel none({});
  const auto unknown = progress_of(active, none, 1025);
  EXPECT_DOUBLE_EQ(unknown.elapsed_s, 25.0);
  EXPECT_FALSE(unknown.left_s);
  EXPECT_NE(progress_line(active, unknown).find("left ?"), std::string::npos);
  EXPECT_TRUE(progress_json(active, unknown)["left_s"].is_null());

  const DurationModel model({{1, done_order(1, 100)}});
  const auto known = progress_of(active, model, 1025);
  EXPECT_DOUBLE_EQ(*known.left_s, 15.0);                            // TO_DROP takes 20 s to DONE, 5 s of it spent
  EXPECT_DOUBLE_EQ(*progress_of(active, model, 1100).left_s, 0.0);  // overdue: never below 0
}

TEST(Progress, QueuedHasNoEstimateAndEndedOrdersNone) {
  const DurationModel model({{1, done_order(1, 100)}});
  OrderInfo queued = order_with(4, 50, {});
  EXPECT_FALSE(progress_of(queued, model, 60).left_s);
  const OrderInfo done = done_order(5, 300);
  const auto p = progress_of(done, model, 999);
  EXPECT_DOUBLE_EQ(p.elapsed_s, 51.0);
  EXPECT_EQ(progress_line(done, p).find("left"), std::string::npos);
}

TEST(DurationModel, ARequeuedOrderCountsFromItsLastAssignment) {
  const OrderInfo requeued = order_with(6, 0,
                                        {{1, {"ASSIGNED", ""}},
                                         {2, {"ACTIVE", "TO_PICK"}},
                                         {5, {"QUEUED", ""}},
                                         {10, {"ASSIGNED", ""}},
                                         {11, {"ACTIVE", "TO_PICK"}},
                                         {30, {"DONE", ""}}});
  const DurationModel model({{6, requeued}});
  EXPECT_DOUBLE_EQ(*model.mean_work(), 20.0);
  EXPECT_DOUBLE_EQ(*model.mean_to_done("TO_PICK"), 19.0);
}
