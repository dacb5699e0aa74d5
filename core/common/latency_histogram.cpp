#include "common/latency_histogram.hpp"

#include <algorithm>
#include <cmath>

namespace fleet {

void LatencyHistogram::add(double seconds) {
  if (!(seconds > kMinSeconds)) seconds = kMinSeconds;  // NaN and negatives too
  const double position = std::log10(seconds / kMinSeconds) * kBinsPerDecade;
  const auto last = static_cast<double>(bins_.size() - 1);
  // Bin i holds (10^(i/20), 10^((i+1)/20)] µs.
  const auto bin = static_cast<std::size_t>(std::clamp(std::ceil(position) - 1.0, 0.0, last));
  ++bins_[bin];
  ++count_;
  sum_ += seconds;
  max_ = std::max(max_, seconds);
}

double LatencyHistogram::quantile(double q) const {
  const auto wanted = static_cast<std::int64_t>(std::ceil(q * static_cast<double>(count_)));
  std::int64_t seen = 0;
  for (std::size_t i = 0; i < bins_.size(); ++i) {
    seen += bins_[i];
    if (seen >= wanted) {
      const double upper = kMinSeconds * std::pow(10.0, static_cast<double>(i + 1) / kBinsPerDecade);
      return std::min(upper, max_);
    }
  }
  return max_;
}

LatencyHistogram::Figures LatencyHistogram::figures() const {
  if (count_ == 0) return {};
  return {count_, quantile(0.5), quantile(0.99), max_, sum_ / static_cast<double>(count_)};
}

}  // namespace fleet
