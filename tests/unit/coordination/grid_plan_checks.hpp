#pragma once

// What every grid plan must keep, checked the same way for each planner.

#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "coordination/grid_map.hpp"

namespace fleet::coordination::test {

inline GridMap parse(const std::string& rows, int height, int width) {
  std::istringstream in("type octile\nheight " + std::to_string(height) + "\nwidth " + std::to_string(width) +
                        "\nmap\n" + rows);
  return parse_grid_map(in, "test.map");
}

/// No two robots in one cell, no swap, no ring of robots moving into each other's cells.
inline void expect_executable(const std::vector<std::vector<int>>& cells, int step) {
  std::map<int, int> at_before, at_after;
  for (std::size_t r = 0; r < cells.size(); ++r) {
    at_before[cells[r][step - 1]] = static_cast<int>(r);
    ASSERT_TRUE(at_after.emplace(cells[r][step], static_cast<int>(r)).second) << "vertex conflict at step " << step;
  }
  for (std::size_t r = 0; r < cells.size(); ++r) {
    // Follow who moves into whose cell; coming back to r is a swap or a ring.
    int follower = static_cast<int>(r);
    for (std::size_t hops = 0; hops <= cells.size(); ++hops) {
      const int cell = cells[follower][step - 1];
      if (cells[follower][step] == cell) break;
      const auto leader = at_before.find(cells[follower][step]);
      if (leader == at_before.end()) break;
      ASSERT_NE(leader->second, static_cast<int>(r)) << "robots move round a ring at step " << step;
      follower = leader->second;
    }
  }
}

}  // namespace fleet::coordination::test
