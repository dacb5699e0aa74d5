#include "monitor/robot_health.hpp"

#include <gtest/gtest.h>

using namespace fleet::monitor;

TEST(RobotHealth, AHeardFromRobotIsAlive) {
  EXPECT_EQ(robot_health({.lost = false, .stalled = false, .silent_s = 0.1, .lost_after_s = 2.0}), RobotHealth::kAlive);
  EXPECT_EQ(robot_health({.lost = false, .stalled = false, .silent_s = 1.0, .lost_after_s = 2.0}), RobotHealth::kAlive);
}

TEST(RobotHealth, SilentForHalfTheLostTimeIsStale) {
  EXPECT_EQ(robot_health({.lost = false, .stalled = false, .silent_s = 1.01, .lost_after_s = 2.0}),
            RobotHealth::kStale);
}

TEST(RobotHealth, AStalledRobotIsStaleAtOnce) {
  EXPECT_EQ(robot_health({.lost = false, .stalled = true, .silent_s = 0.0, .lost_after_s = 2.0}), RobotHealth::kStale);
}

TEST(RobotHealth, ALostRobotIsLostWhateverItsSilence) {
  EXPECT_EQ(robot_health({.lost = true, .stalled = false, .silent_s = 0.0, .lost_after_s = 2.0}), RobotHealth::kLost);
  EXPECT_EQ(to_string(RobotHealth::kLost), "lost");
}

TEST(RobotHealth, SilentLongerThanTheLostTimeIsLost) {
  EXPECT_FALSE(silent_too_long(2.0, 2.0));
  EXPECT_TRUE(silent_too_long(2.01, 2.0));
}
