#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "coordination/grid_map.hpp"

namespace fleet::coordination {

/// The fewest actions (forward, quarter turn) from every (cell, heading) to a goal cell, computed
/// once per goal by a breadth-first search backwards over the states and kept. This is the
/// planner's heuristic: exact for one robot alone on the map.
class HeadingDistances {
 public:
  static constexpr std::uint16_t kUnreachable = 0xFFFF;

  explicit HeadingDistances(const GridMap& map) : map_(map) {}

  /// Actions from (cell, heading) to `goal`; kUnreachable when there is no way.
  int to(int goal, int cell, int heading) { return table(goal)[static_cast<std::size_t>(cell) * kHeadings + heading]; }
  /// The fewest actions from `cell` to `goal` over the headings a robot may have there.
  int best(int goal, int cell);
  /// The whole table of `goal`, indexed cell x 4 + heading.
  const std::vector<std::uint16_t>& table(int goal);
  std::size_t goals_kept() const { return tables_.size(); }

 private:
  const GridMap& map_;
  std::unordered_map<int, std::vector<std::uint16_t>> tables_;
};

}  // namespace fleet::coordination
