#include "orders/command_intake.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "two_forklifts.hpp"

namespace fleet::orders {
namespace {

/// Site "yard" with obstacle O1 (a 1 m square at (5, 5)) and its revision "yard_closed"; forklifts
/// fl1 (reported, standing at the origin) and fl2 (not reported); order 1 queued, order 2 done.
struct Yard {
  config::FleetConfig config = test::two_forklifts();
  map::Site site;
  std::vector<std::string> maps{"yard", "yard_closed"};
  OrderBook book;
  RobotRoster robots{config};
  bool traffic_on = true;

  Yard() {
    site.name = "yard";
    site.static_obstacles.push_back({"O1", {{4.5, 4.5}, {5.5, 4.5}, {5.5, 5.5}, {4.5, 5.5}}, false});
    RobotEntry& fl1 = robots.entries()["fl1"];
    fl1.id = "fl1";
    fl1.registered = true;
    fl1.last.pose = {0.0, 0.0, 0.0};
    Order draft;
    draft.pick_area = "A1";
    draft.drop_area = "A2";
    book.create(draft, 0.0);
    const std::int64_t done = book.create(draft, 0.0).id;
    EXPECT_EQ(book.assign(done, "fl1", 0.0), TransitionResult::kApplied);
    EXPECT_EQ(book.transition(done, OrderStatus::kDone, 1.0), TransitionResult::kApplied);
  }

  CommandDecision decide(const std::string& verb, const std::string& target, const std::string& value = "") const {
    model::Command command;
    command.request_id = "c1";
    command.verb = verb;
    command.target = target;
    command.value = value;
    return decide_command(
        command,
        {.book = book, .site = site, .maps = maps, .config = config, .robots = robots, .traffic_on = traffic_on});
  }
};

TEST(CommandIntake, AnOpenOrderIsCancelledAndAnEndedOrAnUnknownOneIsRefused) {
  Yard yard;
  const auto taken = yard.decide("cancel-order", "1");
  EXPECT_EQ(taken.error, "");
  EXPECT_EQ(taken.action, CommandAction::kCancelOrder);
  EXPECT_EQ(taken.order_id, 1);
  EXPECT_EQ(yard.decide("cancel-order", "2").error, "order 2 is already DONE");
  EXPECT_EQ(yard.decide("cancel-order", "7").error, "unknown order 7");
  EXPECT_EQ(yard.decide("cancel-order", "1x").error, "order id '1x' is not a number");
  EXPECT_EQ(yard.decide("cancel-order", "1x").action, CommandAction::kNone);
}

TEST(CommandIntake, AnObstacleIsNeverSwitchedOnOverARobot) {
  Yard yard;
  const auto on = yard.decide("obstacle", "O1", "on");
  EXPECT_EQ(on.error, "");
  EXPECT_EQ(on.action, CommandAction::kSwitchObstacle);
  EXPECT_TRUE(on.on);
  yard.robots.entries()["fl1"].last.pose = {5.0, 5.2, 0.0};
  EXPECT_EQ(yard.decide("obstacle", "O1", "on").error,
            "obstacle O1 covers robot fl1 at (5.00, 5.20): switch it on once the robot has left");
  const auto off = yard.decide("obstacle", "O1", "off");
  EXPECT_EQ(off.error, "") << "switching it off over a robot is fine";
  EXPECT_FALSE(off.on);
  EXPECT_EQ(yard.decide("obstacle", "O1", "half").error, "obstacle state 'half' is not on or off");
  EXPECT_NE(yard.decide("obstacle", "O9", "on").error.find("O9"), std::string::npos);
}

TEST(CommandIntake, OneRobotChangesMapsOnlyWithTrafficControlOff) {
  Yard yard;
  EXPECT_EQ(yard.decide("map", "", "yard_closed").action, CommandAction::kSwitchMap);
  EXPECT_EQ(yard.decide("map", "all", "yard").action, CommandAction::kNone) << "the map served already";
  EXPECT_EQ(yard.decide("map", "all", "yard").error, "");
  EXPECT_NE(yard.decide("map", "fl1", "yard_closed").error.find("traffic control needs every robot"),
            std::string::npos);
  yard.traffic_on = false;
  EXPECT_EQ(yard.decide("map", "fl1", "yard_closed").action, CommandAction::kMapOneRobot);
  EXPECT_NE(yard.decide("map", "fl9", "yard_closed").error.find("fl9"), std::string::npos);
  EXPECT_NE(yard.decide("map", "", "elsewhere").error.find("elsewhere"), std::string::npos);
}

TEST(CommandIntake, OnlyARobotThatReportedIsPaused) {
  Yard yard;
  const auto pause = yard.decide("pause", "fl1");
  EXPECT_EQ(pause.action, CommandAction::kPauseRobot);
  EXPECT_TRUE(pause.on);
  EXPECT_FALSE(yard.decide("resume", "fl1").on);
  EXPECT_NE(yard.decide("pause", "fl2").error, "") << "fl2 never reported";
  EXPECT_NE(yard.decide("pause", "fl9").error.find("fl9"), std::string::npos);
}

TEST(CommandIntake, AutoOrdersTakeOnOrOffAndUnknownVerbsAreNamed) {
  Yard yard;
  EXPECT_TRUE(yard.decide("auto-orders", "", "on").on);
  EXPECT_EQ(yard.decide("auto-orders", "", "off").action, CommandAction::kAutoOrders);
  EXPECT_EQ(yard.decide("auto-orders", "", "maybe").error, "auto-orders value 'maybe' is not on or off");
  EXPECT_EQ(yard.decide("dance", "fl1").error,
            "unknown command 'dance' (cancel-order, obstacle, map, auto-orders, pause, resume)");
}

}  // namespace
}  // namespace fleet::orders
