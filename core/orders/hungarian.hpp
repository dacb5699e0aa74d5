#pragma once

#include <vector>

namespace fleet::orders {

/// Minimum-cost assignment (Hungarian algorithm, Kuhn-Munkres with potentials, O(n^2 m)).
/// `cost` has n rows and m columns with n <= m. Returns, for each row, its column. Entries of
/// kForbidden (or larger) must not be chosen; if a row can only take a forbidden column it gets
/// -1.
std::vector<int> hungarian_assignment(const std::vector<std::vector<double>>& cost);

inline constexpr double kForbidden = 1e12;

}  // namespace fleet::orders
