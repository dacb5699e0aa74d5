#pragma once

#include <cstdint>
#include <vector>

namespace fleet {

/// How late a fixed-rate control loop runs its steps against the clock it follows.
///
/// A step simulates and controls the period up to its end time; it is late by how far the clock
/// had passed that end when the step ran. The lateness of every step since the start goes into
/// a histogram of 1/20 of a period per bin (up to 50 periods; later ones count as 50), so the
/// median and the 99th percentile cover the whole run at a fixed cost. Steps the loop skipped
/// (it fell so far behind that it jumped the clock instead of replaying the time) are counted
/// apart.
class StepLagMeter {
 public:
  /// Throws std::invalid_argument for a period that is not positive.
  explicit StepLagMeter(double period_s);

  /// A step ran `lateness_s` after the end of the period it covers (negative counts as 0).
  void step_ran(double lateness_s);
  /// The loop jumped over `count` steps.
  void steps_skipped(std::int64_t count);

  struct Figures {
    double p50_s = 0.0;  ///< median lateness, seconds of the clock followed
    double p99_s = 0.0;  ///< 99th percentile; the upper edge of its bin
    double max_s = 0.0;
    std::int64_t steps = 0;    ///< steps run
    std::int64_t skipped = 0;  ///< steps jumped over
  };
  Figures figures() const;
  double period() const { return period_; }

 private:
  double quantile(double q) const;

  double period_;
  double bin_;
  std::vector<std::int64_t> bins_;
  std::int64_t steps_ = 0;
  std::int64_t skipped_ = 0;
  double max_ = 0.0;
};

}  // namespace fleet
