#include "traffic/conflict_zones.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace fleet::traffic {

using geometry::Polygon;
using geometry::Vec2;

geometry::Polygon convex_hull(std::vector<Vec2> points) {
  std::sort(points.begin(), points.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  Polygon hull(2 * points.size());
  std::size_t k = 0;
  for (const Vec2& p : points) {
    while (k >= 2 && geometry::cross(hull[k - 1] - hull[k - 2], p - hull[k - 2]) <= 0.0) --k;
    hull[k++] = p;
  }
  const std::size_t lower = k + 1;
  for (auto it = points.rbegin() + 1; it != points.rend(); ++it) {
    while (k >= lower && geometry::cross(hull[k - 1] - hull[k - 2], *it - hull[k - 2]) <= 0.0) --k;
    hull[k++] = *it;
  }
  hull.resize(k - 1);
  return hull;
}

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

}  // namespace

ConflictZones::ConflictZones(const map::RoadGraph& graph, const ResourceParams& params) : params_(params) {
  if (!(params.margin >= 0.0) || !(params.footprint.length > 0.0) || !(params.footprint.width > 0.0)) {
    throw std::invalid_argument("traffic ResourceParams: footprint length and width must be > 0 and margin >= 0 (margin=" +
                                std::to_string(params.margin) + ")");
  }
  const std::size_t n = graph.points.size();
  if (graph.successors.size() != n) throw std::invalid_argument("traffic ConflictZones: successors size differs from points size");

  // Undirected point adjacency.
  std::vector<std::vector<int>> adjacent(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int j : graph.successors[i]) {
      if (j < 0 || static_cast<std::size_t>(j) >= n) throw std::invalid_argument("traffic ConflictZones: edge to unknown point");
      adjacent[i].push_back(j);
      adjacent[static_cast<std::size_t>(j)].push_back(static_cast<int>(i));
    }
  }
  for (auto& a : adjacent) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  auto pos = [&](std::size_t i) { return Vec2{graph.points[i].x, graph.points[i].y}; };

  // Places: points joined by (near) zero-length edges or lying on top of each other. A sweep along
  // x finds coincident points that no edge joins.
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto unite = [&](int a, int b) {
    a = find_root(parent, a);
    b = find_root(parent, b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  };
  std::vector<int> by_x(n);
  std::iota(by_x.begin(), by_x.end(), 0);
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) { return graph.points[static_cast<std::size_t>(a)].x < graph.points[static_cast<std::size_t>(b)].x; });
  const double eps = params.coincident_distance;
  for (std::size_t a = 0; a < n; ++a) {
    const auto ia = static_cast<std::size_t>(by_x[a]);
    for (std::size_t b = a + 1; b < n; ++b) {
      const auto ib = static_cast<std::size_t>(by_x[b]);
      if (graph.points[ib].x - graph.points[ia].x > eps) break;
      if (geometry::distance(pos(ia), pos(ib)) <= eps) unite(by_x[a], by_x[b]);
    }
  }
  place_of_.assign(n, -1);
  std::vector<std::vector<int>> members;
  for (std::size_t i = 0; i < n; ++i) {
    const auto root = static_cast<std::size_t>(find_root(parent, static_cast<int>(i)));
    if (place_of_[root] < 0) {
      place_of_[root] = static_cast<int>(members.size());
      members.emplace_back();
      position_.push_back(pos(root));
    }
    place_of_[i] = place_of_[root];
    members[static_cast<std::size_t>(place_of_[i])].push_back(static_cast<int>(i));
  }
  const std::size_t places = members.size();

  // Place adjacency and regions.
  neighbours_.assign(places, {});
  region_.assign(places, {});
  std::vector<double> reach(places, 0.0);
  const double grow = params.margin / 2.0;
  for (std::size_t p = 0; p < places; ++p) {
    std::vector<double> headings;
    for (int i : members[p]) {
      for (int j : adjacent[static_cast<std::size_t>(i)]) {
        const int q = place_of_[static_cast<std::size_t>(j)];
        if (static_cast<std::size_t>(q) == p) continue;
        neighbours_[p].push_back(q);
        const Vec2 a = pos(static_cast<std::size_t>(i));
        const Vec2 b = pos(static_cast<std::size_t>(j));
        const double heading = std::atan2(b.y - a.y, b.x - a.x);
        const Vec2 mid = 0.5 * (a + b);
        Polygon corners = geometry::footprint_polygon({a.x, a.y, heading}, params.footprint, grow);
        const Polygon far = geometry::footprint_polygon({mid.x, mid.y, heading}, params.footprint, grow);
        corners.insert(corners.end(), far.begin(), far.end());
        region_[p].push_back(convex_hull(std::move(corners)));
        headings.push_back(heading);
      }
    }
    if (region_[p].empty()) {
      // An isolated place: the robot may stand there at any heading.
      const Vec2 a = position_[p];
      for (double heading : {0.0, std::acos(0.0)}) {
        region_[p].push_back(geometry::footprint_polygon({a.x, a.y, heading}, params.footprint, grow));
      }
    }
    std::sort(neighbours_[p].begin(), neighbours_[p].end());
    neighbours_[p].erase(std::unique(neighbours_[p].begin(), neighbours_[p].end()), neighbours_[p].end());
    for (const Polygon& poly : region_[p]) {
      for (const Vec2& v : poly) reach[p] = std::max(reach[p], geometry::distance(v, position_[p]));
    }
  }

  // Conflicts: a sweep along x bounds the candidate pairs by the largest region reach.
  conflicts_.assign(places, {});
  const double max_reach = places == 0 ? 0.0 : *std::max_element(reach.begin(), reach.end());
  std::vector<int> order(places);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return position_[static_cast<std::size_t>(a)].x < position_[static_cast<std::size_t>(b)].x; });
  for (std::size_t a = 0; a < places; ++a) {
    const auto pa = static_cast<std::size_t>(order[a]);
    conflicts_[pa].push_back(static_cast<int>(pa));
    for (std::size_t b = a + 1; b < places; ++b) {
      const auto pb = static_cast<std::size_t>(order[b]);
      if (position_[pb].x - position_[pa].x > reach[pa] + max_reach) break;
      if (geometry::distance(position_[pa], position_[pb]) > reach[pa] + reach[pb]) continue;
      bool overlap = false;
      for (const Polygon& ra : region_[pa]) {
        for (const Polygon& rb : region_[pb]) {
          if (geometry::convex_polygons_overlap(ra, rb)) {
            overlap = true;
            break;
          }
        }
        if (overlap) break;
      }
      if (overlap) {
        conflicts_[pa].push_back(static_cast<int>(pb));
        conflicts_[pb].push_back(static_cast<int>(pa));
      }
    }
  }
  for (auto& c : conflicts_) std::sort(c.begin(), c.end());

  // Branches and stoppable places.
  branch_.assign(places, 0);
  for (std::size_t p = 0; p < places; ++p) branch_[p] = neighbours_[p].size() >= 3 ? 1 : 0;
  stoppable_.assign(places, 1);
  for (std::size_t p = 0; p < places; ++p) {
    for (int q : conflicts_[p]) {
      if (branch_[static_cast<std::size_t>(q)]) {
        stoppable_[p] = 0;
        break;
      }
    }
  }

  // Corridors: chains of non-branch places, indexed from one end (or anywhere on a loop).
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

bool ConflictZones::conflict(int place_a, int place_b) const {
  const auto& c = conflicts_[static_cast<std::size_t>(place_a)];
  return std::binary_search(c.begin(), c.end(), place_b);
}

int ConflictZones::corridor_direction(int place_a, int place_b) const {
  if (place_a < 0 || place_b < 0 || place_a == place_b) return 0;
  const int c = corridor(place_a);
  if (c < 0 || c != corridor(place_b)) return 0;
  int d = corridor_index(place_b) - corridor_index(place_a);
  if (corridor_is_loop(c) && std::abs(d) > 1) d = d > 0 ? -1 : 1;
  return d > 0 ? 1 : (d < 0 ? -1 : 0);
}

}  // namespace fleet::traffic
