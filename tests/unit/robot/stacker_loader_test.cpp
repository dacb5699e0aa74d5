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

// A loader job's transporter stands behind the picker, facing away, its forks towards it
// (orders::transporter_pose): a move order to that pose reverses it in like into a bay, in the
// rack aisles' lanes on either face.
TEST(Stacker, ReversesIntoThePoseBehindAPickerAtARackPlace) {
  PlantStacker plant;
  for (const std::string place : {"RB2", "RB7", "RB13"}) {
    const geometry::Pose2 goal = plant.behind_picker_at(place);
    auto stacker = plant.make("PT2");
    stacker->set_standing_loads(plant.loads);
    task::TaskOrder order;
    order.order_id = "9";
    order.kind = orders::OrderKind::kMove;
    order.drop_area_id = "behind " + place;
    order.drop_area = goal;
    std::string why;
    ASSERT_TRUE(stacker->submit(order, &why)) << why;
    bool done = false;
    for (int i = 0; i < 20 * 240 && !done; ++i) {
      stacker->step();
      for (const auto& e : stacker->take_events()) done = done || e.kind == RobotEvent::Kind::kDone;
    }
    ASSERT_TRUE(done) << place << ": " << stacker->status().task_state << " (" << stacker->status().detail << ")";
    const geometry::Pose2 at = stacker->status().truth;
    EXPECT_LT(geometry::distance(at.position(), goal.position()), 0.06) << place;
    EXPECT_LT(std::abs(geometry::angle_diff(at.yaw, goal.yaw)), 0.035) << place;
  }
}

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
