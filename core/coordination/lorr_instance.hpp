#pragma once

#include <string>
#include <vector>

#include "coordination/grid_map.hpp"

namespace fleet::coordination {

/// A League of Robot Runners 2023 problem: a grid, where the robots start (facing east), and the
/// errand cells handed out round robin (robot i's n-th errand is line i + n x team size of the task
/// file, read again from the top when it runs out). Locations are row x width + column.
struct LorrInstance {
  std::string path;  ///< the instance file
  GridMap map;
  std::vector<int> starts;  ///< teamSize cells
  std::vector<int> tasks;   ///< errand cells, in file order
  int tasks_revealed = 1;   ///< numTasksReveal: errands a robot knows ahead
};

/// Reads an instance file (`mapFile`, `agentFile`, `taskFile` relative to it, `teamSize`,
/// `numTasksReveal`, `taskAssignmentStrategy`: only `roundrobin`). InputError naming the file and
/// key, or the file and line, on anything missing or wrong: a start or errand off the map or on a
/// blocked cell, fewer starts than the team, two robots on one cell.
LorrInstance load_lorr_instance(const std::string& path);

/// A file of integers as the competition writes them: a count, then that many lines of one
/// integer each (lines starting with '#' skipped). At most `limit` are read when limit >= 0.
std::vector<int> read_location_file(const std::string& path, const std::string& key, int limit);

}  // namespace fleet::coordination
