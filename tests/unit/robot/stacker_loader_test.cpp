// A loader job's transporter on the plant (docs/loader.md): a stacker standing behind a picker,
// moving up behind it, and holding its pallet until its order names the drop place.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "plant_stacker.hpp"
#include "robot/stacker/stacker_job.hpp"

using namespace fleet;
using fleet::test::PlantStacker;
using robot::RobotEvent;
using robot::StackerState;

// Behind a picker that moved on to the next place along the aisle, the transporter backs up
// 3.5 m straight along its line, forks first (StackerEvent::kMoveUp): no route round the loop.
TEST(Stacker, MovesUpStraightBackBehindAPickerThatMovedOn) {
  PlantStacker plant;
  auto stacker = plant.make("PT2");
  stacker->set_standing_loads(plant.loads);
  const auto behind = [&](const std::string& place) { return plant.behind_picker_at(place); };
  double seconds = 0.0, metres = 0.0;
  bool swept = false;
  const auto run = [&](const std::string& place) {
    task::TaskOrder order;
    order.order_id = place;
    order.kind = orders::OrderKind::kMove;
    order.drop_area_id = "behind " + place;
    order.drop_area = behind(place);
    std::string why;
    if (!stacker->submit(order, &why)) return why;
    const double start = stacker->status().time;
    geometry::Vec2 last = stacker->status().truth.position();
    metres = 0.0;
    swept = false;
    for (int i = 0; i < 20 * 240; ++i) {
      swept = swept || !stacker->traffic_route().work_area.empty();
      stacker->step();
      metres += geometry::distance(last, stacker->status().truth.position());
      last = stacker->status().truth.position();
      for (const auto& e : stacker->take_events()) {
        if (e.kind == RobotEvent::Kind::kDone) {
          seconds = stacker->status().time - start;
          return std::string();
        }
      }
    }
    return std::string("not there: ") + stacker->status().task_state + " (" + stacker->status().detail + ")";
  };
  ASSERT_EQ(run("RB2"), "");
  // The picker walks on to RB1, 3.5 m further west; the stacker faces east, its forks west.
  ASSERT_EQ(run("RB1"), "");
  const geometry::Pose2 at = stacker->status().truth;
  EXPECT_LT(geometry::distance(at.position(), behind("RB1").position()), 0.03);
  EXPECT_LT(std::abs(geometry::angle_diff(at.yaw, behind("RB1").yaw)), 0.035);
  EXPECT_LT(metres, 3.7) << "straight back, not round the loop";
  EXPECT_LT(seconds, 14.0);
  EXPECT_TRUE(swept) << "traffic is told what the move sweeps";
}

// A loader's transporter: it lifts a pallet with no drop place named, stands with it behind the
// picker at RB2 (its route, then reversing in), moves up behind RB1 straight back and behind RB3
// straight ahead, and takes the pallet to EX1 once the order names it, each step an update of the
// one transport.
TEST(Stacker, HoldsItsPalletWhereTheOrderHasItStandUntilTheOrderNamesTheDropPlace) {
  PlantStacker plant;
  auto stacker = plant.make("PT2");
  stacker->set_standing_loads(plant.loads);
  const auto behind = [&](const std::string& place) { return plant.behind_picker_at(place); };
  task::TaskOrder order = plant.transport("FG5", "EX1");
  order.drop_area_id.clear();
  order.drop_area = {};
  std::string why;
  ASSERT_TRUE(stacker->submit(order, &why)) << why;
  int lifted = -1, put_down = -1;
  const auto run_until = [&](const std::function<bool()>& there, double seconds) {
    const double end = stacker->status().time + seconds;
    while (stacker->status().time < end && !there()) {
      stacker->step();
      for (const auto& e : stacker->take_events()) {
        if (e.kind == RobotEvent::Kind::kLifted) lifted = e.load_id;
        if (e.kind == RobotEvent::Kind::kDone) put_down = e.load_id;
        if (e.kind == RobotEvent::Kind::kFailed) ADD_FAILURE() << e.text;
      }
    }
    return there();
  };
  const auto holding = [&] { return stacker->state() == StackerState::kHolding; };
  ASSERT_TRUE(run_until(holding, 200.0)) << stacker->status().task_state << " (" << stacker->status().detail << ")";
  EXPECT_EQ(lifted, plant.load_at.at("FG5"));

  // RB2, then RB1 straight back, then RB3 straight ahead (the walk down the aisle's lane).
  for (const std::string place : {"RB2", "RB1", "RB3"}) {
    task::TaskOrder update = order;
    update.stand = behind(place);
    ASSERT_TRUE(stacker->submit(update, &why)) << why;
    const double start = stacker->status().time;
    stacker->step();
    ASSERT_TRUE(run_until(holding, 240.0)) << place << ": " << stacker->status().task_state;
    const geometry::Pose2 at = stacker->status().truth;
    EXPECT_LT(geometry::distance(at.position(), behind(place).position()), 0.06) << place;
    EXPECT_EQ(stacker->status().carried_load, lifted) << place;
    if (place == "RB1") {
      EXPECT_LT(stacker->status().time - start, 15.0) << "moved up straight back";
    }
    if (place == "RB3") {
      EXPECT_LT(stacker->status().time - start, 25.0) << "moved up straight ahead, 7 m, not round the loop";
    }
  }
  task::TaskOrder drop = order;
  drop.drop_area_id = "EX1";
  drop.drop_area = plant.site->site.find_area("EX1")->pose;
  ASSERT_TRUE(stacker->submit(drop, &why)) << why;
  ASSERT_TRUE(run_until([&] { return put_down >= 0; }, 300.0))
      << stacker->status().task_state << " (" << stacker->status().detail << ")";
  EXPECT_EQ(put_down, lifted);
}

// A loader's transporter comes to stand behind the picker at every rack place of the plant: by
// road into the lane a few metres short of the stand, then straight on along the stand's line, in
// the lane's direction, its body never over a rack (the stand's side lies 3 cm from the rack face).
TEST(Stacker, ReachesTheStandBehindAPickerAlongItsLaneAtEveryRackPlace) {
  PlantStacker plant;
  const geometry::Vec2 pick_place = plant.site->site.find_area("FG5")->pose.position();
  for (int n = 1; n <= 24; ++n) {
    const std::string place = "RB" + std::to_string(n);
    const geometry::Pose2 stand = plant.behind_picker_at(place);
    auto stacker = plant.make("PT2");
    stacker->set_standing_loads(plant.loads);
    task::TaskOrder order = plant.transport("FG5", "EX1");
    order.drop_area_id.clear();
    order.drop_area = {};
    std::string why;
    ASSERT_TRUE(stacker->submit(order, &why)) << why;
    double sent_at = -1.0;
    bool stood = false;
    std::string over_rack;
    for (int i = 0; i < 20 * 400 && !stood; ++i) {
      stacker->step();
      for (const auto& e : stacker->take_events()) {
        if (e.kind == RobotEvent::Kind::kFailed) ADD_FAILURE() << place << ": " << e.text;
      }
      if (sent_at < 0.0 && stacker->state() == StackerState::kHolding) {
        task::TaskOrder update = order;
        update.stand = stand;
        ASSERT_TRUE(stacker->submit(update, &why)) << why;
        sent_at = stacker->status().time;
        stacker->step();
        continue;
      }
      if (sent_at < 0.0) continue;
      stood = stacker->state() == StackerState::kHolding;
      const robot::RobotStatus status = stacker->status();
      // A centimetre inside its outline: the side at the stand is 3 cm from the rack face.
      const auto body = geometry::footprint_polygon(status.truth, status.footprint, -0.01);
      for (const auto& rack : plant.site->site.racks) {
        // The finished-goods row's edge, which its forks reach over at FG5, is not in its way.
        if (geometry::segment_polygon_distance(pick_place, pick_place, rack.polygon) < 1.0) continue;
        if (over_rack.empty() && geometry::polygons_overlap(body, rack.polygon)) {
          over_rack = rack.id + " at t = " + std::to_string(status.time) + " in " + status.task_state;
        }
      }
    }
    ASSERT_TRUE(stood) << place << ": " << stacker->status().task_state << " (" << stacker->status().detail << ")";
    EXPECT_EQ(over_rack, "") << place;
    const geometry::Pose2 at = stacker->status().truth;
    EXPECT_LT(geometry::distance(at.position(), stand.position()), 0.04) << place;
    EXPECT_LT(std::abs(geometry::angle_diff(at.yaw, stand.yaw)), 0.035) << place;
    EXPECT_LT(stacker->status().time - sent_at, 120.0) << place;
  }
}
