#include "traffic/one_way.hpp"

#include <algorithm>
#include <functional>
#include <utility>

namespace fleet::traffic {

namespace {

/// Every corridor's ends: the places with the lowest and highest index, its size, and whether
/// all its places lie inside junctions.
struct CorridorEnds {
  std::vector<int> low, high, size;
  std::vector<std::uint8_t> all_in_junction;
};

CorridorEnds corridor_ends(const ConflictZones& zones) {
  const std::size_t corridors = zones.corridor_count();
  CorridorEnds ends{std::vector<int>(corridors, -1), std::vector<int>(corridors, -1), std::vector<int>(corridors, 0),
                    std::vector<std::uint8_t>(corridors, 1)};
  for (std::size_t p = 0; p < zones.place_count(); ++p) {
    const int c = zones.corridor(static_cast<int>(p));
    if (c < 0) continue;
    const auto sc = static_cast<std::size_t>(c);
    ++ends.size[sc];
    if (zones.stoppable(static_cast<int>(p))) ends.all_in_junction[sc] = 0;
    const int i = zones.corridor_index(static_cast<int>(p));
    if (i == 0) ends.low[sc] = static_cast<int>(p);
    if (ends.high[sc] < 0 || i > zones.corridor_index(ends.high[sc])) ends.high[sc] = static_cast<int>(p);
  }
  return ends;
}

/// Per corridor, the way the graph's own edges inside it run: +1 / -1 every one that way, 2 both
/// ways, 0 none.
std::vector<int> given_directions(const map::RoadGraph& graph, const ConflictZones& zones) {
  std::vector<int> given(zones.corridor_count(), 0);
  for (std::size_t i = 0; i < graph.points.size(); ++i) {
    const int pa = zones.place_of(static_cast<int>(i));
    for (int j : graph.successors[i]) {
      const int d = zones.corridor_direction(pa, zones.place_of(j));
      if (d == 0) continue;
      int& g = given[static_cast<std::size_t>(zones.corridor(pa))];
      g = g == 0 || g == d ? d : 2;
    }
  }
  return given;
}

bool directed_by_graph(const std::vector<int>& given, std::size_t corridor) {
  return given[corridor] == 1 || given[corridor] == -1;
}

int branch_next_to(const ConflictZones& zones, int place) {
  for (int q : zones.neighbours(place)) {
    if (zones.branch(q)) return q;
  }
  return -1;
}

struct JunctionEdge {
  int a = 0, b = 0;  ///< branch places at the corridor's low and high ends
  int corridor = 0;
};

/// Branch places linked by the corridors that may be oriented (edges) and by two-way links:
/// junction interiors, branch places next to each other, two-way corridors.
struct JunctionGraph {
  std::vector<JunctionEdge> edges;
  std::vector<std::vector<std::pair<int, int>>> adjacency;  ///< per place: (neighbour, edge index or -1)
};

JunctionGraph junction_graph(const ConflictZones& zones, const CorridorEnds& ends, const std::vector<int>& given) {
  const std::size_t corridors = zones.corridor_count();
  JunctionGraph g;
  g.adjacency.resize(zones.place_count());
  for (std::size_t c = 0; c < corridors; ++c) {
    if (ends.size[c] < 2 || ends.all_in_junction[c] || zones.corridor_is_loop(static_cast<int>(c))) continue;
    if (directed_by_graph(given, c)) continue;
    const int a = branch_next_to(zones, ends.low[c]);
    const int b = branch_next_to(zones, ends.high[c]);
    if (a < 0 || b < 0 || a == b) continue;  // dead ends and tiny loops stay two-way
    g.edges.push_back({a, b, static_cast<int>(c)});
  }
  for (std::size_t e = 0; e < g.edges.size(); ++e) {
    g.adjacency[static_cast<std::size_t>(g.edges[e].a)].push_back({g.edges[e].b, static_cast<int>(e)});
    g.adjacency[static_cast<std::size_t>(g.edges[e].b)].push_back({g.edges[e].a, static_cast<int>(e)});
  }
  for (std::size_t c = 0; c < corridors; ++c) {
    if (ends.size[c] == 0 || directed_by_graph(given, c)) continue;
    const bool oriented = std::any_of(g.edges.begin(), g.edges.end(),
                                      [&](const JunctionEdge& e) { return e.corridor == static_cast<int>(c); });
    if (oriented) continue;
    // A two-way corridor joins every branch place it touches.
    std::vector<int> touching;
    for (int end : {ends.low[c], ends.high[c]}) {
      for (int q : zones.neighbours(end)) {
        if (zones.branch(q)) touching.push_back(q);
      }
    }
    for (std::size_t i = 0; i < touching.size(); ++i) {
      for (std::size_t j = i + 1; j < touching.size(); ++j) {
        g.adjacency[static_cast<std::size_t>(touching[i])].push_back({touching[j], -1});
        g.adjacency[static_cast<std::size_t>(touching[j])].push_back({touching[i], -1});
      }
    }
  }
  for (std::size_t p = 0; p < zones.place_count(); ++p) {
    if (!zones.branch(static_cast<int>(p))) continue;
    for (int q : zones.neighbours(static_cast<int>(p))) {
      if (zones.branch(q)) g.adjacency[p].push_back({q, -1});
    }
  }
  return g;
}

/// Per junction edge: +1 a -> b, -1 b -> a, 0 two-way. Depth-first search from `root`: tree edges
/// point away from the root, the others back to the ancestor; bridges (low[child] > order[parent])
/// stay two-way.
std::vector<int> orient_edges(const ConflictZones& zones, const JunctionGraph& g, int root) {
  const std::size_t places = zones.place_count();
  std::vector<int> order(places, -1), low(places, 0);
  std::vector<int> edge_dir(g.edges.size(), 0);
  std::vector<std::uint8_t> edge_seen(g.edges.size(), 0);
  auto direct = [&](int e, int from) {
    edge_seen[static_cast<std::size_t>(e)] = 1;
    edge_dir[static_cast<std::size_t>(e)] = g.edges[static_cast<std::size_t>(e)].a == from ? 1 : -1;
  };
  int counter = 0;
  std::function<void(int, int)> visit = [&](int v, int via_edge) {
    const auto sv = static_cast<std::size_t>(v);
    order[sv] = low[sv] = counter++;
    for (const auto& [w, e] : g.adjacency[sv]) {
      if (e >= 0 && e == via_edge) continue;
      const auto sw = static_cast<std::size_t>(w);
      if (order[sw] < 0) {
        if (e >= 0) direct(e, v);
        visit(w, e);
        low[sv] = std::min(low[sv], low[sw]);
        if (e >= 0 && low[sw] > order[sv]) edge_dir[static_cast<std::size_t>(e)] = 0;  // a bridge
      } else {
        low[sv] = std::min(low[sv], order[sw]);
        if (e >= 0 && !edge_seen[static_cast<std::size_t>(e)]) direct(e, v);
      }
    }
  };
  visit(root, -1);
  for (std::size_t p = 0; p < places; ++p) {
    if (zones.branch(static_cast<int>(p)) && order[p] < 0) visit(static_cast<int>(p), -1);
  }
  return edge_dir;
}

/// Whether the graph edge from place pa to place pb runs against the corridors `oriented` (per
/// corridor: +1 / -1, 0 not oriented here): inside one against its direction, into one other
/// than at its upstream end, out of one other than at its downstream end.
bool against_orientation(const ConflictZones& zones, const CorridorEnds& ends, const std::vector<int>& oriented, int pa,
                         int pb) {
  if (pa == pb) return false;
  const int ca = zones.corridor(pa), cb = zones.corridor(pb);
  if (ca >= 0 && ca == cb) {
    const int o = oriented[static_cast<std::size_t>(ca)];
    return o != 0 && zones.corridor_direction(pa, pb) != o;
  }
  if (cb >= 0 && ca != cb) {
    const auto c = static_cast<std::size_t>(cb);
    const int o = oriented[c];
    if (o != 0 && pb != (o > 0 ? ends.low[c] : ends.high[c])) return true;
  }
  if (ca >= 0 && ca != cb) {
    const auto c = static_cast<std::size_t>(ca);
    const int o = oriented[c];
    if (o != 0 && pa != (o > 0 ? ends.high[c] : ends.low[c])) return true;
  }
  return false;
}

}  // namespace

OneWayPlan one_way_plan(const map::RoadGraph& graph, const ConflictZones& zones) {
  const std::size_t corridors = zones.corridor_count();
  const CorridorEnds ends = corridor_ends(zones);
  // Lanes the graph already drives one way (the two lanes of a two-way road, keep right) keep
  // the direction their edges give: orienting them again could only close them.
  const std::vector<int> given = given_directions(graph, zones);
  const JunctionGraph junctions = junction_graph(zones, ends, given);
  OneWayPlan plan;
  plan.graph = graph;
  plan.corridor_direction.assign(corridors, 0);
  // The root is the first branch place. Other roots and neighbour orders give other
  // orientations; choosing among them by shortest routes or by longest directed cycles was tried
  // on the demo tables and stalled more often in the simulator with 12 robots than this one, so
  // the choice stays simple and deterministic (see the README's traffic section).
  int root = -1;
  for (std::size_t p = 0; p < zones.place_count() && root < 0; ++p) {
    if (zones.branch(static_cast<int>(p))) root = static_cast<int>(p);
  }
  if (root >= 0) {
    const std::vector<int> edge_dir = orient_edges(zones, junctions, root);
    // +1 along the corridor index means from the low end (next to a) to the high end (next to b).
    for (std::size_t e = 0; e < junctions.edges.size(); ++e) {
      plan.corridor_direction[static_cast<std::size_t>(junctions.edges[e].corridor)] = edge_dir[e];
    }
    // Only the corridors oriented here filter edges; lanes directed by the graph stay as given.
    const std::vector<int> oriented = plan.corridor_direction;
    for (std::size_t i = 0; i < graph.points.size(); ++i) {
      const int pa = zones.place_of(static_cast<int>(i));
      auto& next = plan.graph.successors[i];
      next.erase(
          std::remove_if(next.begin(), next.end(),
                         [&](int j) { return against_orientation(zones, ends, oriented, pa, zones.place_of(j)); }),
          next.end());
    }
  }
  for (std::size_t c = 0; c < corridors; ++c) {
    if (directed_by_graph(given, c)) plan.corridor_direction[c] = given[c];
  }
  return plan;
}

}  // namespace fleet::traffic
