#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "common/percentile.hpp"
#include "monitor/aisle_share.hpp"
#include "monitor/collision_monitor.hpp"
#include "monitor/localization_watch.hpp"
#include "monitor/order_accounting.hpp"
#include "monitor/track_recorder.hpp"
#include "orders/server_term.hpp"

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

// A standby took over in term 2 and handed out the ids of its block; the server cut off from it
// went on in term 1's. Between the blocks nothing is missing; the first id of term 2's block is.
TEST(OrderAccounting, TermBlocksAreCountedEachFromItsStartAndTheGapBetweenThemIsNoLoss) {
  std::map<std::int64_t, model::OrderInfo> orders;
  auto add = [&](std::int64_t id) {
    model::OrderInfo info;
    info.order_id = id;
    info.state = "DONE";
    orders[id] = info;
  };
  for (std::int64_t id : {1, 2, 3, 4}) add(id);
  const std::int64_t block = orders::first_order_id(2);
  for (std::int64_t id : {block, block + 1}) add(id);
  OrderTally t = tally_orders(orders, 1);
  EXPECT_EQ(t.created, 6);
  EXPECT_EQ(t.lost, 0);
  orders.erase(block);
  t = tally_orders(orders, 1);
  EXPECT_EQ(t.created, 6);
  EXPECT_EQ(t.lost, 1) << "the first order of the term that took over vanished";
}

TEST(OrderAccounting, DoneOrdersCountByKindWithTheServersOwnTransportsApart) {
  std::map<std::int64_t, model::OrderInfo> orders;
  auto add = [&](std::int64_t id, const char* kind, const char* state, const char* cause = "") {
    model::OrderInfo info;
    info.order_id = id;
    info.kind = kind;
    info.state = state;
    info.cause = cause;
    orders[id] = info;
  };
  add(1, "transport", "DONE");
  add(2, "pick", "DONE");
  add(3, "pick", "DONE");
  add(4, "transport", "DONE", "packing: PS1 full after 2, 3");
  add(5, "pick", "FAILED");
  add(6, "transport", "ACTIVE", "packing: empty pallet for PS1");
  add(7, "move", "DONE");
  const auto done = done_by_kind(orders);
  EXPECT_EQ(done.at("transport"), 1);
  EXPECT_EQ(done.at("pick"), 2);
  EXPECT_EQ(done.at("chained"), 1);
  EXPECT_EQ(done.at("move"), 1);
  EXPECT_EQ(done_by_kind(orders, 4).at("pick"), 0);
  EXPECT_EQ(done_by_kind({}).at("chained"), 0);
}

// Items an hour per working picker: the boxes of the done pick orders over the hours the pickers
// spent on them, from assignment to end.
TEST(OrderAccounting, PickingFiguresCountBoxesOverThePickersHoursOnTheirOrders) {
  std::map<std::int64_t, model::OrderInfo> orders;
  const auto add = [&](std::int64_t id, const std::string& state, const std::string& lines, bool loader,
                       double assigned, double finished) {
    model::OrderInfo& o = orders[id];
    o.order_id = id;
    o.kind = "pick";
    o.state = state;
    o.lines = lines;
    o.loader = loader;
    o.assigned_sim = assigned;
    o.finished_sim = finished;
  };
  add(1, "DONE", "RB1,A1,2\n", false, 0.0, 1800.0);             // a tray tour: 2 boxes in half an hour
  add(2, "DONE", "RB1,A1,3\nRB3,A3,3\n", true, 100.0, 1900.0);  // a loader walk: 6 boxes in half an hour
  add(3, "FAILED", "RB2,A2,1\n", true, 0.0, 50.0);
  add(4, "ACTIVE", "RB2,A2,1\n", true, 0.0, 0.0);
  const PickingFigures f = picking_figures(orders);
  EXPECT_EQ(f.pick_orders_done, 2);
  EXPECT_EQ(f.loader_jobs_done, 1);
  EXPECT_EQ(f.boxes_picked, 8);
  EXPECT_EQ(f.boxes_loaded, 6);
  EXPECT_NEAR(f.picker_hours, 1.0, 1e-12);
  EXPECT_NEAR(f.items_per_hour, 8.0, 1e-12);
  EXPECT_EQ(picking_figures(orders, 2).boxes_picked, 6);
}

TEST(LocalizationWatch, ComparesEachEstimateWithTheTruthOfTheSameStampAndGroupsByFleet) {
  LocalizationWatch watch;
  watch.note_truth("pk1", {1.0, 0.0, 0.0}, 10.0);
  watch.note_estimate("pk1", {1.3, 0.4, 0.0}, 10.0);  // 0.5 m off
  watch.note_estimate("pk1", {9.0, 9.0, 0.0}, 10.5);  // its truth not in yet
  watch.note_truth("pk1", {9.0, 9.1, 0.0}, 10.5);     // now: 0.1 m
  watch.note_truth("pk1", {5.0, 5.0, 0.0}, 11.0);     // no estimate of that stamp
  watch.note_estimate("fk1", {0.0, 0.0, 0.0}, 10.0);
  watch.note_truth("fk1", {0.0, 0.02, 0.0}, 10.0);
  watch.note_truth("fk1", {0.0, 0.03, 0.0}, 10.0);  // the same publication again: counted once
  watch.note_estimate("fk1", {std::nan(""), 0.0, 0.0}, 11.0);
  watch.note_truth("fk1", {0.0, 0.0, 0.0}, 11.0);
  ASSERT_EQ(watch.errors().at("pk1").size(), 2u);
  EXPECT_NEAR(watch.errors().at("pk1")[0], 0.5, 1e-12);
  EXPECT_NEAR(watch.errors().at("pk1")[1], 0.1, 1e-9);
  ASSERT_EQ(watch.errors().at("fk1").size(), 1u);
  EXPECT_NEAR(watch.worst().at("pk1").error, 0.5, 1e-12);
  EXPECT_EQ(watch.worst().at("pk1").sim_time, 10.0);
  EXPECT_EQ(watch.worst().at("pk1").truth.x, 1.0);
  const auto figures = error_figures(watch.errors(), {{"pk1", "pickers"}, {"fk1", "forklifts"}});
  EXPECT_NEAR(figures.at("pickers").max, 0.5, 1e-12);
  EXPECT_EQ(figures.at("pickers").samples, 2);
  EXPECT_NEAR(figures.at("forklifts").p95, 0.02, 1e-12);
}

TEST(LocalizationWatch, ReportsAnEstimateFarOffOnceUntilItComesBack) {
  LocalizationWatch watch(1.0, 0.5);
  double t = 0.0;
  const auto off_by = [&](double error) {
    t += 0.1;
    watch.note_truth("pk1", {0.0, 0.0, 0.0}, t);
    watch.note_estimate("pk1", {error, 0.0, 0.0}, t);
  };
  off_by(0.2);
  EXPECT_TRUE(watch.take_far_off().empty());
  off_by(1.2);
  off_by(3.0);
  off_by(0.7);  // still off: not back under 0.5 m
  off_by(1.5);
  auto reported = watch.take_far_off();
  ASSERT_EQ(reported.size(), 1u);
  EXPECT_EQ(reported[0].robot_id, "pk1");
  EXPECT_NEAR(reported[0].at.error, 1.2, 1e-12);
  EXPECT_NEAR(reported[0].at.estimate.x, 1.2, 1e-12);
  EXPECT_TRUE(watch.take_far_off().empty()) << "taken once";
  off_by(0.3);  // back
  off_by(1.1);  // off again: a new report
  reported = watch.take_far_off();
  ASSERT_EQ(reported.size(), 1u);
  EXPECT_NEAR(reported[0].at.error, 1.1, 1e-12);
}

TEST(AisleShare, FindsTheAislesBetweenFacingRacksAndNotAcrossOthers) {
  const auto rect = [](double x0, double y0, double x1, double y1) {
    return geometry::Polygon{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  };
  const std::vector<std::pair<std::string, geometry::Polygon>> racks{
      {"R1", rect(33.5, 9.0, 54.5, 10.2)},     {"R2", rect(33.5, 13.2, 54.5, 15.6)},
      {"R3", rect(33.5, 18.6, 54.5, 19.8)},    {"FAR", rect(33.5, 30.0, 54.5, 31.0)},
      {"N1", rect(33.44, 10.08, 33.56, 10.2)},  // an upright
  };
  const auto aisles = rack_aisles(racks);
  ASSERT_EQ(aisles.size(), 2u);
  EXPECT_EQ(aisles[0].name, "R1|R2");
  EXPECT_DOUBLE_EQ(aisles[0].box.min_y, 10.2);
  EXPECT_DOUBLE_EQ(aisles[0].box.max_y, 13.2);
  EXPECT_EQ(aisles[1].name, "R2|R3");  // R1|R3 has R2 between them, R3|FAR is too wide
}

TEST(AisleShare, CountsTheTimeTwoPickersWorkOneAisle) {
  AisleShareWatch watch({{"R1|R2", {33.5, 10.2, 54.5, 13.2}}, {"R2|R3", {33.5, 15.6, 54.5, 18.6}}},
                        {"pk1", "pk2", "pk3"});
  for (int k = 0; k <= 300; ++k) {
    const double t = 0.1 * k;
    watch.note("pk1", {40.0, 11.0}, t);  // in the aisle all along
    watch.note("pk2", k >= 50 && k < 150 ? geometry::Vec2{45.0, 12.4} : geometry::Vec2{20.0, 8.0}, t);
    watch.note("pk3", k >= 200 && k < 230 ? geometry::Vec2{50.0, 11.0} : geometry::Vec2{40.0, 17.0}, t);
    watch.note("fk1", {41.0, 11.0}, t);  // not a picker
  }
  EXPECT_NEAR(watch.shared_seconds(), 13.0, 0.11);  // pk2 from 5 s to 15 s, pk3 from 20 s to 23 s
  EXPECT_EQ(watch.times(), 2);
  EXPECT_NEAR(watch.longest_seconds(), 10.0, 0.11);
  EXPECT_EQ(watch.longest_aisle(), "R1|R2");
  EXPECT_EQ(watch.longest_robots(), (std::vector<std::string>{"pk1", "pk2"}));
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
  order(1, "DONE", 100, 160,
        {{100, "QUEUED", "", "", "", 0, 0},
         {100, "ASSIGNED", "", "fl1", "", 0, 0},
         {110, "ACTIVE", "TO_PICK", "fl1", "", 0, 0},
         {160, "DONE", "DROPPING", "fl1", "", 0, 0}});
  order(2, "ACTIVE", 200, 250,
        {{200, "QUEUED", "", "", "", 0, 0},
         {200, "ASSIGNED", "", "fl2", "", 0, 0},
         {250, "QUEUED", "", "", "robot fl2 lost", 0, 0},
         {250, "ASSIGNED", "", "fl1", "", 0, 0}});
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

// The one percentile every printed median, p95 and p99 is: nearest rank, never interpolated.
TEST(Percentile, IsTheValueOfNearestRankNeverInterpolated) {
  EXPECT_DOUBLE_EQ(common::percentile({}, 0.5), 0.0);
  EXPECT_DOUBLE_EQ(common::percentile({3, 1, 2}, 0.5), 2.0);
  EXPECT_DOUBLE_EQ(common::percentile({4, 1, 3, 2}, 0.5), 2.0);  // the lower middle of an even count
  EXPECT_DOUBLE_EQ(common::percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 0.95), 10.0);
  EXPECT_DOUBLE_EQ(common::percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 0.0), 1.0);
  std::vector<double> hundred;
  for (int i = 100; i >= 1; --i) hundred.push_back(i);
  EXPECT_DOUBLE_EQ(common::percentile(hundred, 0.95), 95.0);
  EXPECT_DOUBLE_EQ(common::percentile(hundred, 0.99), 99.0);
  EXPECT_DOUBLE_EQ(common::percentile(hundred, 1.0), 100.0);
  EXPECT_DOUBLE_EQ(common::percentile(hundred, 1.5), 100.0);  // q is clamped to 0..1
}

TEST(TrackRecorder, KeepsTheWindowAtItsRateAndWritesItFromTheRunStart) {
  TrackRecorder tracks(10.0, 0.5);
  for (int i = 0; i <= 300; ++i) {  // 30 s at 10 Hz
    const double t = 100.0 + 0.1 * i;
    tracks.add("fl1", {0.01 * i, 1.0, 0.5}, t);
  }
  tracks.add("fl2", {2.0, 2.0, std::nan("")}, 129.0);  // not a pose: left out
  tracks.add("fl2", {2.0, 2.0, 1.0}, 129.5);
  std::ostringstream csv;
  tracks.write_csv(csv, 125.0, 100.0);
  std::istringstream lines(csv.str());
  std::string line;
  std::getline(lines, line);
  EXPECT_EQ(line, "robot,sim_s,x,y,yaw");
  int fl1 = 0;
  std::string first, last_fl2;
  while (std::getline(lines, line)) {
    if (line.starts_with("fl1")) {
      if (fl1++ == 0) first = line;
    } else {
      last_fl2 = line;
    }
  }
  EXPECT_EQ(first, "fl1,25.00,2.5000,1.0000,0.5000");  // from `since` on, time from the run's start
  EXPECT_EQ(fl1, 11);                                  // 25 .. 30 s, one every 0.5 s
  EXPECT_EQ(last_fl2, "fl2,29.50,2.0000,2.0000,1.0000");
  std::ostringstream all;
  tracks.write_csv(all, 0.0, 100.0);
  EXPECT_EQ(all.str().find("fl1,19.50"), std::string::npos);  // older than the 10 s window: gone
  EXPECT_NE(all.str().find("fl1,20.00"), std::string::npos);
}

TEST(TrackRecorder, WhatItWritesReadsBackAndABadRowIsNamedWithItsLine) {
  TrackRecorder tracks(60.0, 0.1);
  tracks.add("fl2", {1.0, 2.0, 0.5}, 10.0);
  tracks.add("fl1", {0.5, 0.25, -1.0}, 10.0);
  tracks.add("fl1", {0.6, 0.25, -1.0}, 10.5);
  std::stringstream csv;
  tracks.write_csv(csv, 0.0, 4.0);
  const auto read = read_tracks_csv(csv, "deadlock-1-fl1.csv");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].robot_id, "fl1");
  ASSERT_EQ(read[0].poses.size(), 2u);
  EXPECT_DOUBLE_EQ(read[0].sim_s[1], 6.5);
  EXPECT_DOUBLE_EQ(read[0].poses[1].x, 0.6);
  EXPECT_DOUBLE_EQ(read[1].poses[0].yaw, 0.5);

  std::istringstream bad("robot,sim_s,x,y,yaw\nfl1,1.0,0.5,0.5,0.0\nfl1,2.0,0.5,nan,0.0\n");
  try {
    read_tracks_csv(bad, "tracks.csv");
    FAIL() << "a NaN coordinate was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("tracks.csv:3"), std::string::npos) << e.what();
  }
  std::istringstream short_row("fl1,1.0,0.5\n");
  EXPECT_THROW(read_tracks_csv(short_row, "tracks.csv"), std::runtime_error);
}

TEST(CollisionMonitor, PolygonFootprintsCollideOnlyWhereTheirShapesMeet) {
  // A body with its rear corners cut (a reach truck's chamfers): a small robot standing in the cut
  // is inside the rectangle extent but touches nothing.
  const fleet::geometry::Polygon chamfered{{0.8, -0.45}, {0.8, 0.45},   {-0.6, 0.45},
                                           {-0.8, 0.25}, {-0.8, -0.25}, {-0.6, -0.45}};
  const fleet::geometry::Polygon small{{0.05, -0.05}, {0.05, 0.05}, {-0.05, 0.05}, {-0.05, -0.05}};
  fleet::monitor::CollisionMonitor monitor;
  monitor.update("rt1", {0.0, 0.0, 0.0}, chamfered, 1.0);
  EXPECT_TRUE(monitor.update("s1", {-0.79, 0.42, 0.0}, small, 1.0).empty());
  EXPECT_EQ(monitor.update("s1", {-0.5, 0.42, 0.0}, small, 1.02).size(), 1u);
}
