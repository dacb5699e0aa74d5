#pragma once

#include <string>

#include "orders/order.hpp"

namespace fleet::orders {

/// What the active server does with an order a server that stepped down hands over to it.
enum class MergeChoice { kAdopt, kKeepOwn };

struct MergeDecision {
  MergeChoice choice = MergeChoice::kKeepOwn;
  /// Both servers gave it to a robot (or both ended it, differently) while they were cut off from
  /// each other: it ran on both sides.
  bool ran_on_both_sides = false;
  std::string why;
};

/// After a partition, two servers each hold a version of the orders either changed while they
/// were cut off. An order's history only grows, and an order only moves forward (QUEUED, ASSIGNED,
/// ACTIVE, an end), so the version that got further is the one that happened: an order new to
/// the active server is adopted; an ended one beats one still open; of two open ones, the further
/// state, then the longer history; of two ended ones, and on a tie, the active server keeps its
/// own.
MergeDecision merge_handed_over(const Order* own, const Order& theirs);

}  // namespace fleet::orders
