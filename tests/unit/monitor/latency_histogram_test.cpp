#include "common/latency_histogram.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace fleet {
namespace {

TEST(LatencyHistogram, QuantilesReadWithinOneBinAboveTheTrueValue) {
  LatencyHistogram h;
  // 1 ms to 1000 ms in 1 ms steps: median 500 ms, p99 990 ms.
  for (int i = 1; i <= 1000; ++i) h.add(i * 1e-3);
  const auto f = h.figures();
  EXPECT_EQ(f.count, 1000);
  const double bin = std::pow(10.0, 1.0 / LatencyHistogram::kBinsPerDecade);
  EXPECT_GE(f.p50_s, 0.500);
  EXPECT_LE(f.p50_s, 0.500 * bin);
  EXPECT_GE(f.p99_s, 0.990);
  EXPECT_LE(f.p99_s, 1.0);  // never above the maximum
  EXPECT_DOUBLE_EQ(f.max_s, 1.0);
  EXPECT_NEAR(f.mean_s, 0.5005, 1e-9);
}

TEST(LatencyHistogram, ARareSlowSampleMovesP99OnlyWhenItIsMoreThanOnePercent) {
  LatencyHistogram h;
  for (int i = 0; i < 995; ++i) h.add(2e-4);
  for (int i = 0; i < 5; ++i) h.add(0.5);
  EXPECT_LT(h.figures().p99_s, 3e-4);
  EXPECT_DOUBLE_EQ(h.figures().max_s, 0.5);
  for (int i = 0; i < 10; ++i) h.add(0.5);
  EXPECT_GT(h.figures().p99_s, 0.4);
}

TEST(LatencyHistogram, OutOfRangeAndInvalidSamplesAreClampedNotLost) {
  LatencyHistogram h;
  h.add(-1.0);
  h.add(std::nan(""));
  h.add(0.0);
  h.add(1e4);
  const auto f = h.figures();
  EXPECT_EQ(f.count, 4);
  EXPECT_LE(f.p50_s, 1.2e-6);
  EXPECT_DOUBLE_EQ(f.max_s, 1e4);
  EXPECT_EQ(LatencyHistogram().figures().count, 0);
}

}  // namespace
}  // namespace fleet
