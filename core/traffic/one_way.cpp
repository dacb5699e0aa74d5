#include "traffic/one_way.hpp"

#include <algorithm>
#include <functional>

namespace fleet::traffic {

namespace {

struct JunctionEdge {
  int a = 0, b = 0;  ///< branch places at the corridor's low and high ends
  int corridor = 0;
};

}  // namespace

OneWayPlan one_way_plan(const map::RoadGraph& graph, const ConflictZones& zones) {
  const std::size_t places = zones.place_count();
  const std::size_t corridors = zones.corridor_count();
  // Ends of every corridor: the places with the lowest and highest index, and the branch places
  // they touch.
  std::vector<int> low_end(corridors, -1), high_end(corridors, -1), size(corridors, 0);
  std::vector<std::uint8_t> all_in_junction(corridors, 1);
  for (std::size_t p = 0; p < places; ++p) {
    const int c = zones.corridor(static_cast<int>(p));
    if (c < 0) continue;
    const auto sc = static_cast<std::size_t>(c);
    ++size[sc];
    if (zones.stoppable(static_cast<int>(p))) all_in_junction[sc] = 0;
    const int i = zones.corridor_index(static_cast<int>(p));
    if (i == 0) low_end[sc] = static_cast<int>(p);
    if (high_end[sc] < 0 || i > zones.corridor_index(high_end[sc])) high_end[sc] = static_cast<int>(p);
  }
  auto branch_next_to = [&](int place, int other_end_excluded) {
    for (int q : zones.neighbours(place)) {
      if (zones.branch(q) && q != other_end_excluded) return q;
    }
    return -1;
  };
  // Lanes the graph already drives one way (the two lanes of a two-way road, keep right) keep
  // the direction their edges give: orienting them again could only close them.
  std::vector<int> given(corridors, 0);  // +1 / -1: every edge inside runs that way; 2: both ways
  for (std::size_t i = 0; i < graph.points.size(); ++i) {
    const int pa = zones.place_of(static_cast<int>(i));
    for (int j : graph.successors[i]) {
      const int d = zones.corridor_direction(pa, zones.place_of(j));
      if (d == 0) continue;
      int& g = given[static_cast<std::size_t>(zones.corridor(pa))];
      g = g == 0 || g == d ? d : 2;
    }
  }
  const auto directed_by_graph = [&](int c) {
    return given[static_cast<std::size_t>(c)] == 1 || given[static_cast<std::size_t>(c)] == -1;
  };
  std::vector<JunctionEdge> edges;
  for (std::size_t c = 0; c < corridors; ++c) {
    if (size[c] < 2 || all_in_junction[c] || zones.corridor_is_loop(static_cast<int>(c))) continue;
    if (directed_by_graph(static_cast<int>(c))) continue;
    const int a = branch_next_to(low_end[c], -1);
    const int b = branch_next_to(high_end[c], -1);
    if (a < 0 || b < 0 || a == b) continue;  // dead ends and tiny loops stay two-way
    edges.push_back({a, b, static_cast<int>(c)});
  }
  // Two-way links between branch places: junction interiors and branch places next to each other.
  std::vector<std::vector<std::pair<int, int>>> adjacency(places);  // (neighbour, edge index or -1)
  for (std::size_t e = 0; e < edges.size(); ++e) {
    adjacency[static_cast<std::size_t>(edges[e].a)].push_back({edges[e].b, static_cast<int>(e)});
    adjacency[static_cast<std::size_t>(edges[e].b)].push_back({edges[e].a, static_cast<int>(e)});
  }
  for (std::size_t c = 0; c < corridors; ++c) {
    if (size[c] == 0 || directed_by_graph(static_cast<int>(c))) continue;
    const bool oriented = std::any_of(edges.begin(), edges.end(),
                                      [&](const JunctionEdge& e) { return e.corridor == static_cast<int>(c); });
    if (oriented) continue;
    // A two-way corridor joins every branch place it touches.
    std::vector<int> touching;
    for (int end : {low_end[c], high_end[c]}) {
      for (int q : zones.neighbours(end)) {
        if (zones.branch(q)) touching.push_back(q);
      }
    }
    for (std::size_t i = 0; i < touching.size(); ++i) {
      for (std::size_t j = i + 1; j < touching.size(); ++j) {
        adjacency[static_cast<std::size_t>(touching[i])].push_back({touching[j], -1});
        adjacency[static_cast<std::size_t>(touching[j])].push_back({touching[i], -1});
      }
    }
  }
  for (std::size_t p = 0; p < places; ++p) {
    if (!zones.branch(static_cast<int>(p))) continue;
    for (int q : zones.neighbours(static_cast<int>(p))) {
      if (zones.branch(q)) adjacency[p].push_back({q, -1});
    }
  }

  // Depth-first search from `root`: tree edges point away from the root, the others back to the
  // ancestor; bridges (low[child] > order[parent]) stay two-way.
  auto orient = [&](int root, bool reversed) {
    std::vector<int> order(places, -1), low(places, 0);
    std::vector<int> edge_dir(edges.size(), 0);  // +1: a -> b, -1: b -> a, 0: two-way
    std::vector<std::uint8_t> edge_seen(edges.size(), 0);
    int counter = 0;
    std::function<void(int, int)> visit = [&](int v, int via_edge) {
      const auto sv = static_cast<std::size_t>(v);
      order[sv] = low[sv] = counter++;
      const auto& next = adjacency[sv];
      for (std::size_t k = 0; k < next.size(); ++k) {
        const auto& [w, e] = next[reversed ? next.size() - 1 - k : k];
        if (e >= 0 && e == via_edge) continue;
        const auto sw = static_cast<std::size_t>(w);
        if (order[sw] < 0) {
          if (e >= 0) {
            edge_seen[static_cast<std::size_t>(e)] = 1;
            edge_dir[static_cast<std::size_t>(e)] = edges[static_cast<std::size_t>(e)].a == v ? 1 : -1;
          }
          visit(w, e);
          low[sv] = std::min(low[sv], low[sw]);
          if (e >= 0 && low[sw] > order[sv]) edge_dir[static_cast<std::size_t>(e)] = 0;  // a bridge
        } else {
          low[sv] = std::min(low[sv], order[sw]);
          if (e >= 0 && !edge_seen[static_cast<std::size_t>(e)]) {
            edge_seen[static_cast<std::size_t>(e)] = 1;
            edge_dir[static_cast<std::size_t>(e)] = edges[static_cast<std::size_t>(e)].a == v ? 1 : -1;
          }
        }
      }
    };
    visit(root, -1);
    for (std::size_t p = 0; p < places; ++p) {
      if (zones.branch(static_cast<int>(p)) && order[p] < 0) visit(static_cast<int>(p), -1);
    }

    OneWayPlan plan;
    plan.corridor_direction.assign(corridors, 0);
    for (std::size_t e = 0; e < edges.size(); ++e) {
      // +1 along the corridor index means from the low end (next to a) to the high end (next to b).
      plan.corridor_direction[static_cast<std::size_t>(edges[e].corridor)] = edge_dir[e];
    }
    // Only the corridors oriented here filter edges; lanes directed by the graph stay as given.
    const std::vector<int> oriented = plan.corridor_direction;
    for (std::size_t c = 0; c < corridors; ++c) {
      if (directed_by_graph(static_cast<int>(c))) plan.corridor_direction[c] = given[c];
    }
    plan.graph = graph;
    for (std::size_t i = 0; i < graph.points.size(); ++i) {
      const int pa = zones.place_of(static_cast<int>(i));
      auto& next = plan.graph.successors[i];
      next.erase(std::remove_if(next.begin(), next.end(),
                                [&](int j) {
                                  const int pb = zones.place_of(j);
                                  if (pa == pb) return false;
                                  const int ca = zones.corridor(pa), cb = zones.corridor(pb);
                                  if (ca >= 0 && ca == cb) {
                                    const int o = oriented[static_cast<std::size_t>(ca)];
                                    return o != 0 && zones.corridor_direction(pa, pb) != o;
                                  }
                                  // Entering a one-way corridor: only at its upstream end. Leaving: only at its
                                  // downstream end.
                                  if (cb >= 0 && ca != cb) {
                                    const int o = oriented[static_cast<std::size_t>(cb)];
                                    if (o != 0 && pb != (o > 0 ? low_end[static_cast<std::size_t>(cb)]
                                                               : high_end[static_cast<std::size_t>(cb)]))
                                      return true;
                                  }
                                  if (ca >= 0 && ca != cb) {
                                    const int o = oriented[static_cast<std::size_t>(ca)];
                                    if (o != 0 && pa != (o > 0 ? high_end[static_cast<std::size_t>(ca)]
                                                               : low_end[static_cast<std::size_t>(ca)]))
                                      return true;
                                  }
                                  return false;
                                }),
                 next.end());
    }
    return plan;
  };

  // The root is the first branch place. Other roots and neighbour orders give other
  // orientations; choosing among them by shortest routes or by longest directed cycles was tried
  // on the demo tables and stalled more often in the simulator with 12 robots than this one, so
  // the choice stays simple and deterministic (see the README's traffic section).
  for (std::size_t root = 0; root < places; ++root) {
    if (zones.branch(static_cast<int>(root))) return orient(static_cast<int>(root), false);
  }
  OneWayPlan none;
  none.graph = graph;
  none.corridor_direction.assign(corridors, 0);
  for (std::size_t c = 0; c < corridors; ++c) {
    if (directed_by_graph(static_cast<int>(c))) none.corridor_direction[c] = given[c];
  }
  return none;
}

}  // namespace fleet::traffic
