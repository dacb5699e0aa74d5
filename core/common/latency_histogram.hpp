#pragma once

#include <array>
#include <cstdint>

namespace fleet {

/// Durations in log-spaced bins, 20 per decade from 1 µs to 100 s (shorter ones count as 1 µs,
/// longer as 100 s): the median and 99th percentile of any number of samples at a fixed cost. A
/// quantile reads as the upper edge of its bin, at most 12 % above the true value; the maximum
/// is exact.
class LatencyHistogram {
 public:
  void add(double seconds);

  struct Figures {
    std::int64_t count = 0;
    double p50_s = 0.0;
    double p99_s = 0.0;
    double max_s = 0.0;
    double mean_s = 0.0;
  };
  Figures figures() const;

  static constexpr int kBinsPerDecade = 20;
  static constexpr double kMinSeconds = 1e-6;
  static constexpr int kDecades = 8;

 private:
  double quantile(double q) const;

  std::array<std::int64_t, kBinsPerDecade * kDecades> bins_{};
  std::int64_t count_ = 0;
  double sum_ = 0.0;
  double max_ = 0.0;
};

}  // namespace fleet
