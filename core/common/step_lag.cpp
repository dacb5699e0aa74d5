#include "common/step_lag.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fleet {

namespace {
constexpr int kBinsPerPeriod = 20;
constexpr int kPeriods = 50;
}  // namespace

StepLagMeter::StepLagMeter(double period_s)
    : period_(period_s), bin_(period_s / kBinsPerPeriod), bins_(kBinsPerPeriod * kPeriods + 1, 0) {
  if (!(period_s > 0.0)) throw std::invalid_argument("step lag: the control period must be positive");
}

void StepLagMeter::step_ran(double lateness_s) {
  const double late = std::isfinite(lateness_s) ? std::max(0.0, lateness_s) : 0.0;
  const auto bin = static_cast<std::size_t>(std::min(late / bin_, static_cast<double>(bins_.size() - 1)));
  ++bins_[bin];
  ++steps_;
  max_ = std::max(max_, late);
}

void StepLagMeter::steps_skipped(std::int64_t count) {
  skipped_ += std::max<std::int64_t>(0, count);
}

double StepLagMeter::quantile(double q) const {
  if (steps_ == 0) return 0.0;
  // The smallest bin edge below which at least q of the steps fall.
  const auto wanted = static_cast<std::int64_t>(std::ceil(q * static_cast<double>(steps_)));
  std::int64_t seen = 0;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    seen += bins_[i];
    if (seen < wanted) continue;
    // The last bin holds everything beyond the range: it reads as the largest seen.
    return i + 1 == bins_.size() ? max_ : std::min(max_, static_cast<double>(i + 1) * bin_);
  }
  return max_;
}

StepLagMeter::Figures StepLagMeter::figures() const {
  return {quantile(0.5), quantile(0.99), max_, steps_, skipped_};
}

}  // namespace fleet
