#include "orders/dispatcher.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace fleet::orders {
namespace {

/// Loading areas A1 to A4, a pallet on A1 and one on A3; forklifts fl1 (at x = 0) and fl2 (at
/// x = 10) of fleet "forklifts", both idle; travel cost is the distance along x.
struct Yard {
  OrderBook book;
  AreaLedger ledger{
      {{"A1", {0.0, 0.0, 0.0}}, {"A2", {2.0, 0.0, 0.0}}, {"A3", {4.0, 0.0, 0.0}}, {"A4", {6.0, 0.0, 0.0}}}};
  std::map<std::string, RobotEntry> robots;
  std::vector<FleetAbility> abilities{{"forklifts", {}, 0.0, {}}};
  std::map<std::string, double> area_x{{"A1", 0.0}, {"A2", 2.0}, {"A3", 4.0}, {"A4", 6.0}};
  std::vector<std::string> taken_places;
  Dispatcher dispatcher{make_dispatch_policy("nearest")};

  Yard() {
    ledger.record({1, "pallet", {}, "A1", ""});
    ledger.record({2, "pallet", {}, "A3", ""});
    for (const auto& [id, x] : {std::pair{"fl1", 0.0}, std::pair{"fl2", 10.0}}) {
      RobotEntry& robot = robots[id];
      robot.id = id;
      robot.fleet_id = "forklifts";
      robot.registered = true;
      robot.last.robot_id = id;
      robot.last.pose = {x, 0.0, 0.0};
      robot.last.task_state = "IDLE";
    }
  }

  std::int64_t transport(const std::string& pick, const std::string& drop) {
    Order draft;
    draft.pick_area = pick;
    draft.drop_area = drop;
    return book.create(draft, 0.0).id;
  }

  std::vector<Assignment> round(double now_wall = 100.0) const {
    return dispatcher.round({.book = book,
                             .ledger = ledger,
                             .robots = robots,
                             .abilities = abilities,
                             .place_taken =
                                 [&](const std::string& place) {
                                   return std::find(taken_places.begin(), taken_places.end(), place) !=
                                          taken_places.end();
                                 },
                             .cost =
                                 [&](const std::string& robot_id, const std::string& area_id) {
                                   return std::abs(robots.at(robot_id).last.pose.x - area_x.at(area_id));
                                 },
                             .now_wall = now_wall,
                             .held = {}});
  }
};

TEST(Dispatcher, AReadyTransportGoesToTheNearestFreeRobot) {
  Yard yard;
  const auto id = yard.transport("A3", "A4");
  const auto assignments = yard.round();
  ASSERT_EQ(assignments.size(), 1u);
  EXPECT_EQ(assignments[0].order_id, id);
  EXPECT_EQ(assignments[0].robot_id, "fl1") << "4 m from A3 against 6 m";
}

TEST(Dispatcher, ATransportWaitsForItsLoadItsDropAndBodiesOnEither) {
  Yard yard;
  yard.transport("A2", "A4");  // nothing stands on A2
  yard.transport("A1", "A3");  // A3 holds a pallet
  EXPECT_TRUE(yard.round().empty());
  EXPECT_TRUE(Dispatcher::offered(yard.book, yard.ledger, {}).empty());
  const auto ready = yard.transport("A1", "A4");
  yard.taken_places = {"A4"};
  EXPECT_TRUE(yard.round().empty()) << "a robot's body stands on the drop";
  yard.taken_places.clear();
  const OrderHeld hold_it = [&](const Order& order) { return order.id == ready; };
  EXPECT_TRUE(Dispatcher::offered(yard.book, yard.ledger, {}, hold_it).empty()) << "an order held back is not offered";
  const auto assignments = yard.round();
  ASSERT_EQ(assignments.size(), 1u);
  EXPECT_EQ(assignments[0].order_id, ready);
}

TEST(Dispatcher, OnlyHeardIdleUnloadedRobotsWithoutAnOrderTakeNewWork) {
  Yard yard;
  const RobotEntry& fl1 = yard.robots.at("fl1");
  EXPECT_TRUE(yard.dispatcher.takes_new_work(fl1, yard.book, 0.0));
  for (const char* state : {"GO_HOME", "PARKING"}) {
    RobotEntry robot = fl1;
    robot.last.task_state = state;
    EXPECT_TRUE(yard.dispatcher.takes_new_work(robot, yard.book, 0.0)) << state;
  }
  RobotEntry busy = fl1;
  busy.last.task_state = "TO_PICK";
  EXPECT_FALSE(yard.dispatcher.takes_new_work(busy, yard.book, 0.0));
  RobotEntry loaded = fl1;
  loaded.last.carrying_pallet = true;
  EXPECT_FALSE(yard.dispatcher.takes_new_work(loaded, yard.book, 0.0));
  RobotEntry lost = fl1;
  lost.lost = true;
  EXPECT_FALSE(yard.dispatcher.takes_new_work(lost, yard.book, 0.0));
  RobotEntry unheard = fl1;
  unheard.registered = false;
  EXPECT_FALSE(yard.dispatcher.takes_new_work(unheard, yard.book, 0.0));
  const auto id = yard.transport("A1", "A2");
  ASSERT_EQ(yard.book.assign(id, "fl1", 0.0), TransitionResult::kApplied);
  EXPECT_FALSE(yard.dispatcher.takes_new_work(fl1, yard.book, 0.0)) << "it holds an open order";
}

TEST(Dispatcher, ARobotThatRejectedAnOrderIsOfferedNoneForAWhile) {
  Yard yard;
  yard.transport("A1", "A2");
  yard.dispatcher.rejected("fl1", 100.0);
  auto assignments = yard.round(100.5);
  ASSERT_EQ(assignments.size(), 1u);
  EXPECT_EQ(assignments[0].robot_id, "fl2") << "fl1 backs off although it is nearer";
  assignments = yard.round(100.0 + Dispatcher::kRejectionBackoffWallS);
  ASSERT_EQ(assignments.size(), 1u);
  EXPECT_EQ(assignments[0].robot_id, "fl1");
}

TEST(Dispatcher, RobotsOfAFleetWithoutAbilitiesAreNotOffered) {
  Yard yard;
  yard.transport("A1", "A2");
  yard.abilities.clear();
  EXPECT_TRUE(yard.round().empty());
}

}  // namespace
}  // namespace fleet::orders
