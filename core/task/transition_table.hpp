#pragma once

#include <deque>
#include <optional>
#include <ranges>
#include <set>
#include <utility>
#include <vector>

namespace fleet::task {

/// A row of a job's transition table: from a state, on an event, to a state (and whatever else the
/// job's rows carry). Every (state, event) pair a table does not list is refused.
template <typename Row>
concept JobRow = requires(const Row& row) {
  row.from;
  row.event;
  row.to;
};

// The one engine of the jobs that are transition tables (the stacker's job, the picker's
// navigation, arm and localization supervisors): the lookup, and the checks every such table
// passes in its tests.

/// A table: any range of rows (a std::array, a std::span, a C array).
template <typename Table>
concept JobTable = std::ranges::input_range<Table> && JobRow<std::ranges::range_value_t<Table>>;
template <JobTable Table>
using RowOf = std::ranges::range_value_t<Table>;
template <JobTable Table>
using StateOf = decltype(RowOf<Table>::from);
template <JobTable Table>
using EventOf = decltype(RowOf<Table>::event);

/// The state `event` leads to from `from`: the `to` of the table's row for that pair, or nothing.
template <JobTable Table>
std::optional<StateOf<Table>> next_state(const Table& table, StateOf<Table> from, EventOf<Table> event) {
  for (const auto& row : table) {
    if (row.from == from && row.event == event) return row.to;
  }
  return std::nullopt;
}

/// The rows whose (from, event) pair an earlier row lists already: none in a well-formed table.
template <JobTable Table>
std::vector<RowOf<Table>> repeated_rows(const Table& table) {
  std::set<std::pair<int, int>> seen;
  std::vector<RowOf<Table>> repeated;
  for (const auto& row : table) {
    if (!seen.insert({static_cast<int>(row.from), static_cast<int>(row.event)}).second) repeated.push_back(row);
  }
  return repeated;
}

/// Every state some sequence of events leads to from `start`, `start` included.
template <JobTable Table>
std::set<StateOf<Table>> reachable_states(const Table& table, StateOf<Table> start) {
  std::set<StateOf<Table>> seen{start};
  std::deque<StateOf<Table>> open{start};
  while (!open.empty()) {
    const auto state = open.front();
    open.pop_front();
    for (const auto& row : table) {
      if (row.from == state && seen.insert(row.to).second) open.push_back(row.to);
    }
  }
  return seen;
}

}  // namespace fleet::task
