#include "model/senders.hpp"

#include <gtest/gtest.h>

#include "common/log_limiter.hpp"

namespace fleet {
namespace {

using model::judge_sender;
using model::SenderVerdict;

TEST(Senders, ARobotsPartitionSpeaksForThatRobotAlone) {
  EXPECT_EQ(judge_sender({"robot.fl1"}, "fl1", true), SenderVerdict::kAccepted);
  EXPECT_EQ(judge_sender({"robot.fl1"}, "fl1", false), SenderVerdict::kAccepted);
  EXPECT_EQ(judge_sender({"robot.fl2"}, "fl1", true), SenderVerdict::kAnotherRobotsName);
  EXPECT_EQ(judge_sender({"robot.fl2"}, "fl1", false), SenderVerdict::kAnotherRobotsName);
  EXPECT_EQ(judge_sender({"robot.fl1", "robot.fl2"}, "fl1", true), SenderVerdict::kAnotherRobotsName);
  EXPECT_EQ(judge_sender({"robot.*"}, "fl1", true), SenderVerdict::kAnotherRobotsName);
}

TEST(Senders, TheDefaultPartitionSpeaksForAnyRobotOnlyWithoutSecurity) {
  EXPECT_EQ(judge_sender({}, "fl1", false), SenderVerdict::kAccepted);
  EXPECT_EQ(judge_sender({""}, "fl1", false), SenderVerdict::kAccepted);
  EXPECT_EQ(judge_sender({}, "fl1", true), SenderVerdict::kOutsideAnyPartition);
  EXPECT_EQ(judge_sender({""}, "fl1", true), SenderVerdict::kOutsideAnyPartition);
}

TEST(LogLimiter, TheFirstIsLoggedThenOneLineAnIntervalWithTheCountHeldBack) {
  LogLimiter limiter(10.0);
  long held = -1;
  int lines = 0;
  long held_total = 0;
  // 20 a second for a minute from one sender.
  for (int k = 0; k < 1200; ++k) {
    if (limiter.allow("writer-1/pose", k / 20.0, held)) {
      ++lines;
      held_total += held;
    }
  }
  EXPECT_EQ(lines, 6);
  EXPECT_EQ(held_total + lines, 1200 - 199);  // those of the last, unfinished interval are still held
  EXPECT_TRUE(limiter.allow("writer-2/pose", 1.0, held)) << "another sender is limited on its own";
  EXPECT_EQ(held, 0);
}

}  // namespace
}  // namespace fleet
