#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

namespace fleet::coordination {

/// Headings on a grid, in the League of Robot Runners' numbering: 0 east, 1 south, 2 west,
/// 3 north; a clockwise turn adds one.
inline constexpr int kHeadings = 4;
inline int clockwise(int heading) {
  return (heading + 1) % kHeadings;
}
inline int counter_clockwise(int heading) {
  return (heading + kHeadings - 1) % kHeadings;
}
/// Quarter turns from `from` to `to`, the shorter way round (0, 1 or 2).
inline int quarter_turns(int from, int to) {
  const int d = (to - from + kHeadings) % kHeadings;
  return d == 3 ? 1 : d;
}
/// 'E', 'S', 'W' or 'N'.
char heading_letter(int heading);

/// A grid site: every free cell is a place; a robot moves one cell forward, turns a quarter, or
/// waits. Cells are numbered row x cols + column, as the MovingAI and competition files do.
struct GridMap {
  int rows = 0;
  int cols = 0;
  std::vector<std::uint8_t> free;  ///< per cell: 1 when a robot may stand there
  std::string source;              ///< the file it came from, for messages

  int cells() const { return rows * cols; }
  bool is_free(int cell) const { return cell >= 0 && cell < cells() && free[cell] != 0; }
  int free_cells() const;
  /// The cell one step from `cell` towards `heading`, or -1 when that leaves the map or is blocked.
  int step(int cell, int heading) const;
  /// The heading from `from` to its neighbour `to`; -1 when they are not neighbours.
  int heading_between(int from, int to) const;
  /// "row,col" of a cell, for messages.
  std::string describe(int cell) const;
  /// The states (cell x 4 + heading) one action before `state`: the cell behind by a forward move
  /// (-1 when that is a wall or off the map) and the two quarter turns in place.
  std::array<int, 3> predecessors(int state) const {
    const int cell = state / kHeadings;
    const int h = state % kHeadings;
    const int behind = step(cell, (h + 2) % kHeadings);
    return {behind >= 0 ? behind * kHeadings + h : -1, cell * kHeadings + clockwise(h),
            cell * kHeadings + counter_clockwise(h)};
  }
};

/// What `fleetctl map check` tells of a grid site: its free cells, how they hang together (four
/// neighbours), and the dead ends (one free neighbour), where robots have to make room for each
/// other.
struct GridReport {
  int rows = 0;
  int cols = 0;
  int free_cells = 0;
  int components = 0;         ///< sets of free cells connected by moves
  int largest_component = 0;  ///< free cells in the largest
  int dead_ends = 0;
};
GridReport check_grid_map(const GridMap& map);
std::string format_grid_report(const GridReport& report, const std::string& name);

/// Reads a MovingAI map (`type octile`, `height`, `width`, `map`, then rows of `.`, `E`, `S`, `G`
/// free and `@`, `T`, `O`, `W` blocked). InputError naming the file and line on anything else.
GridMap load_grid_map(const std::string& path);
GridMap parse_grid_map(std::istream& in, const std::string& source);

}  // namespace fleet::coordination
