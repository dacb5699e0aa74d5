#include "common/step_lag.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace fleet {
namespace {

constexpr double kPeriod = 1.0 / 70.0;

TEST(StepLagMeter, AnOnTimeLoopShowsItsSmallLatenessAtTheMedianAndP99) {
  StepLagMeter meter(kPeriod);
  for (int i = 0; i < 1000; ++i) meter.step_ran(0.1 * kPeriod * (i % 3));  // 0, 0.1, 0.2 periods
  const auto f = meter.figures();
  EXPECT_EQ(f.steps, 1000);
  EXPECT_EQ(f.skipped, 0);
  EXPECT_NEAR(f.p50_s, 0.1 * kPeriod, 0.05 * kPeriod + 1e-12);
  EXPECT_NEAR(f.p99_s, 0.2 * kPeriod, 0.05 * kPeriod + 1e-12);
  EXPECT_LT(f.p99_s, kPeriod);
  EXPECT_NEAR(f.max_s, 0.2 * kPeriod, 1e-12);
}

TEST(StepLagMeter, TwoPercentOfStepsLateByThreePeriodsPutP99BeyondAPeriod) {
  StepLagMeter meter(kPeriod);
  for (int i = 0; i < 980; ++i) meter.step_ran(0.0);
  for (int i = 0; i < 20; ++i) meter.step_ran(3.0 * kPeriod);
  const auto f = meter.figures();
  EXPECT_NEAR(f.p50_s, 0.0, 0.05 * kPeriod);
  EXPECT_NEAR(f.p99_s, 3.0 * kPeriod, 0.05 * kPeriod + 1e-12);
  EXPECT_GT(f.p99_s, kPeriod);
}

TEST(StepLagMeter, LatenessBeyondItsRangeAndSkippedStepsStillCount) {
  StepLagMeter meter(kPeriod);
  meter.step_ran(500.0 * kPeriod);  // far beyond the 50 periods binned
  meter.step_ran(-1.0);             // a step ahead of the clock is on time
  meter.steps_skipped(69);
  const auto f = meter.figures();
  EXPECT_EQ(f.steps, 2);
  EXPECT_EQ(f.skipped, 69);
  EXPECT_NEAR(f.max_s, 500.0 * kPeriod, 1e-9);
  EXPECT_NEAR(f.p99_s, 500.0 * kPeriod, 1e-9);  // the top bin reads as the largest seen
  EXPECT_NEAR(f.p50_s, 0.0, 0.05 * kPeriod + 1e-12);
  EXPECT_THROW(StepLagMeter(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace fleet
