#include "coordination/heading_distances.hpp"

#include <algorithm>

namespace fleet::coordination {

int HeadingDistances::best(int goal, int cell) {
  const auto& t = table(goal);
  int best = kUnreachable;
  for (int h = 0; h < kHeadings; ++h) best = std::min<int>(best, t[static_cast<std::size_t>(cell) * kHeadings + h]);
  return best;
}

const std::vector<std::uint16_t>& HeadingDistances::table(int goal) {
  if (const auto it = tables_.find(goal); it != tables_.end()) return it->second;
  std::vector<std::uint16_t> dist(static_cast<std::size_t>(map_.cells()) * kHeadings, kUnreachable);
  std::vector<int> queue;
  queue.reserve(dist.size());
  if (map_.is_free(goal)) {
    for (int h = 0; h < kHeadings; ++h) {
      dist[static_cast<std::size_t>(goal) * kHeadings + h] = 0;
      queue.push_back(goal * kHeadings + h);
    }
  }
  // Backwards: the predecessors of (cell, h) are (cell - step(h), h) by a forward move and
  // (cell, h +- 1) by a turn, each one action away.
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int state = queue[head];
    const std::uint16_t d = dist[state] + 1;
    for (const int p : map_.predecessors(state)) {
      if (p >= 0 && dist[p] == kUnreachable) {
        dist[p] = d;
        queue.push_back(p);
      }
    }
  }
  return tables_.emplace(goal, std::move(dist)).first->second;
}

}  // namespace fleet::coordination
