#pragma once

// Small road graphs built in code, every edge driven both ways unless built one way.

#include <algorithm>
#include <cmath>
#include <vector>

#include "map/road_graph.hpp"

namespace fleet::traffic::testing {

class GraphBuilder {
 public:
  /// The point at (x, y), created when new.
  int point(double x, double y) {
    for (const auto& p : graph_.points) {
      if (std::abs(p.x - x) < 1e-9 && std::abs(p.y - y) < 1e-9) return p.id;
    }
    map::GraphPoint p;
    p.id = static_cast<int>(graph_.points.size());
    p.x = x;
    p.y = y;
    graph_.points.push_back(p);
    graph_.successors.emplace_back();
    return p.id;
  }
  void link(int a, int b) {
    auto add = [&](int u, int v) {
      auto& s = graph_.successors[static_cast<std::size_t>(u)];
      for (int w : s) {
        if (w == v) return;
      }
      s.push_back(v);
    };
    add(a, b);
    add(b, a);
  }
  /// An edge driven from a to b only.
  void arc(int a, int b) {
    auto& s = graph_.successors[static_cast<std::size_t>(a)];
    if (std::find(s.begin(), s.end(), b) == s.end()) s.push_back(b);
  }
  /// A lane from (x0, y0) to (x1, y1) driven that way only, sampled every `spacing`.
  std::vector<int> one_way_road(double x0, double y0, double x1, double y1, double spacing = 0.1) {
    const double length = std::hypot(x1 - x0, y1 - y0);
    const int steps = std::max(1, static_cast<int>(std::lround(length / spacing)));
    std::vector<int> ids;
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      ids.push_back(point(x0 + t * (x1 - x0), y0 + t * (y1 - y0)));
      if (k > 0) arc(ids[ids.size() - 2], ids.back());
    }
    return ids;
  }
  /// A straight road from (x0, y0) to (x1, y1) sampled every `spacing`; returns its point ids.
  std::vector<int> road(double x0, double y0, double x1, double y1, double spacing = 0.1) {
    const double length = std::hypot(x1 - x0, y1 - y0);
    const int steps = std::max(1, static_cast<int>(std::lround(length / spacing)));
    std::vector<int> ids;
    for (int k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      ids.push_back(point(x0 + t * (x1 - x0), y0 + t * (y1 - y0)));
      if (k > 0) link(ids[ids.size() - 2], ids.back());
    }
    return ids;
  }
  const map::RoadGraph& graph() const { return graph_; }

 private:
  map::RoadGraph graph_;
};

/// A corridor from (0, 0) to (2, 0) with a 0.6 m siding spur up from x = 0.5.
inline map::RoadGraph corridor_with_siding() {
  GraphBuilder b;
  b.road(0.0, 0.0, 2.0, 0.0);
  b.road(0.5, 0.0, 0.5, 0.6);
  return b.graph();
}

/// Two ways between junctions L (0, 0) and R (1.5, 0): straight, or round by y = 0.9; a 0.6 m
/// tail beyond each junction.
inline map::RoadGraph two_ways_between_junctions() {
  GraphBuilder b;
  b.road(-0.6, 0.0, 0.0, 0.0);
  b.road(0.0, 0.0, 1.5, 0.0);
  b.road(1.5, 0.0, 2.1, 0.0);
  b.road(0.0, 0.0, 0.0, 0.9);
  b.road(0.0, 0.9, 1.5, 0.9);
  b.road(1.5, 0.9, 1.5, 0.0);
  return b.graph();
}

/// A crossing: four 1 m arms from (0, 0) to (1, 0), (0, 1), (-1, 0), (0, -1).
inline map::RoadGraph plus_junction(double arm = 1.0) {
  GraphBuilder b;
  b.road(0.0, 0.0, arm, 0.0);
  b.road(0.0, 0.0, 0.0, arm);
  b.road(0.0, 0.0, -arm, 0.0);
  b.road(0.0, 0.0, 0.0, -arm);
  return b.graph();
}

inline int point_at(const map::RoadGraph& g, double x, double y) {
  for (const auto& p : g.points) {
    if (std::abs(p.x - x) < 1e-6 && std::abs(p.y - y) < 1e-6) return p.id;
  }
  return -1;
}

}  // namespace fleet::traffic::testing
