#pragma once

#include <vector>

namespace fleet::common {

/// The q-quantile (q in 0..1) of `values` by the nearest-rank definition: the value of rank
/// ceil(q * n) in ascending order (rank 1 at least), so the p95 of 20 values is the 19th and the
/// median of an even count the lower middle one; always one of the values, never interpolated.
/// 0 for no values. Every figure Fleet prints as a median, p95 or p99 is this one
/// (docs/testing.md, "Medians and percentiles").
double percentile(std::vector<double> values, double q);

}  // namespace fleet::common
