// Corridors and opposite lanes of ConflictZones: the facts the traffic manager's direction rules
// read, split from the regions and conflicts they derive from.

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "traffic/conflict_zones.hpp"

namespace fleet::traffic {

using geometry::Vec2;

void ConflictZones::build_corridors() {
  // Corridors: chains of non-branch places, indexed from one end (or anywhere on a loop).
  const std::size_t places = position_.size();
  corridor_.assign(places, -1);
  corridor_index_.assign(places, -1);
  auto chain_neighbours = [&](std::size_t p) {
    std::vector<int> out;
    for (int q : neighbours_[p]) {
      if (!branch_[static_cast<std::size_t>(q)]) out.push_back(q);
    }
    return out;
  };
  for (std::size_t start = 0; start < places; ++start) {
    if (branch_[start] || corridor_[start] >= 0) continue;
    // Walk to one end of the chain (or once round a loop).
    std::size_t end = start;
    std::size_t previous = places;
    bool loop = false;
    while (true) {
      std::size_t step = places;
      for (int q : chain_neighbours(end)) {
        if (static_cast<std::size_t>(q) != previous) {
          step = static_cast<std::size_t>(q);
          break;
        }
      }
      if (step == places) break;
      if (step == start) {
        loop = true;
        break;
      }
      previous = end;
      end = step;
    }
    if (loop) end = start;
    const int id = static_cast<int>(corridor_size_.size());
    int index = 0;
    std::size_t at = end;
    previous = places;
    while (true) {
      corridor_[at] = id;
      corridor_index_[at] = index++;
      std::size_t step = places;
      for (int q : chain_neighbours(at)) {
        if (static_cast<std::size_t>(q) != previous && corridor_[static_cast<std::size_t>(q)] < 0) {
          step = static_cast<std::size_t>(q);
          break;
        }
      }
      if (step == places) break;
      previous = at;
      at = step;
    }
    corridor_size_.push_back(index);
    corridor_loop_.push_back(loop ? 1 : 0);
  }
}

void ConflictZones::build_opposite_lanes(const map::RoadGraph& graph, const std::vector<std::vector<int>>& members) {
  // Two lanes of one road (OpenDRIVE lane ids of opposite sign) are two corridors. When their
  // places on that road conflict for a pair of types, each stretch on each side — a run of
  // neighbouring places of the corridor in conflict with the other corridor, on the road or on
  // the lanes leading to it — is recorded, so the manager can keep robots driving towards each other
  // from entering it together (the corridor rule, across the centre line). A robot waiting just
  // before its stretch is then clear of every place of the other corridor.
  const std::size_t places = position_.size();
  const std::size_t types = types_.size();
  const std::size_t corridors = corridor_size_.size();
  auto opposite_lane_of_one_road = [&](std::size_t p, std::size_t q) {
    for (int i : members[p]) {
      const auto& a = graph.points[static_cast<std::size_t>(i)];
      if (a.road_id.empty() || a.lane_id == 0) continue;
      for (int j : members[q]) {
        const auto& b = graph.points[static_cast<std::size_t>(j)];
        if (b.road_id == a.road_id && b.lane_id != 0 && (b.lane_id > 0) != (a.lane_id > 0)) return true;
      }
    }
    return false;
  };
  opposite_.assign(types * types, std::vector<std::vector<OppositeLane>>(corridors));
  struct Pair {
    int i = 0, j = 0;
    std::size_t p = 0, q = 0;
  };
  for (std::size_t t = 0; t < types; ++t) {
    for (std::size_t u = 0; u < types; ++u) {
      std::map<std::pair<int, int>, std::vector<Pair>> pairs;  // (corridor, other corridor)
      std::set<std::pair<int, int>> one_road;  // some conflicting pair lies on opposite lanes of one road
      for (std::size_t p = 0; p < places; ++p) {
        const int c = corridor_[p];
        if (c < 0 || corridor_loop_[static_cast<std::size_t>(c)]) continue;
        for (int q : conflicts(static_cast<int>(t), static_cast<int>(p), static_cast<int>(u))) {
          const auto sq = static_cast<std::size_t>(q);
          const int other = corridor_[sq];
          if (other < 0 || other == c || corridor_loop_[static_cast<std::size_t>(other)]) continue;
          pairs[{c, other}].push_back({corridor_index_[p], corridor_index_[sq], p, sq});
          if (opposite_lane_of_one_road(p, sq)) one_road.insert({c, other});
        }
      }
      auto& out = opposite_[pair_index(static_cast<int>(t), static_cast<int>(u))];
      for (auto& [key, found] : pairs) {
        if (!one_road.contains(key)) continue;
        // One stretch per run of neighbouring places in conflict: two lanes that meet only at
        // their ends (where they fan out to a junction) are taken in turn there, and robots pass
        // each other on the stretch between, where their regions never overlap.
        std::sort(found.begin(), found.end(), [](const Pair& a, const Pair& b) { return a.i < b.i; });
        for (std::size_t first = 0; first < found.size();) {
          std::size_t last = first;
          while (last + 1 < found.size() && found[last + 1].i <= found[last].i + 1) ++last;
          Pair lo = found[first], hi = found[first], other_lo = found[first], other_hi = found[first];
          for (std::size_t k = first; k <= last; ++k) {
            if (found[k].i > hi.i) hi = found[k];
            if (found[k].j < other_lo.j) other_lo = found[k];
            if (found[k].j > other_hi.j) other_hi = found[k];
          }
          const Vec2 along = position_[hi.p] - position_[lo.p];
          const Vec2 other_along = position_[other_hi.q] - position_[other_lo.q];
          const double d = geometry::dot(along, other_along);
          const int sign = lo.i == hi.i || other_lo.j == other_hi.j ? 0 : (d > 0.0 ? 1 : (d < 0.0 ? -1 : 0));
          out[static_cast<std::size_t>(key.first)].push_back({key.second, sign, lo.i, hi.i, other_lo.j, other_hi.j});
          has_opposite_lanes_ = true;
          first = last + 1;
        }
      }
    }
  }
}

}  // namespace fleet::traffic
