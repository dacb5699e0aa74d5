#pragma once

// Graphs and sites built in code, so planning tests do not depend on map files.

#include <cmath>
#include <random>

#include "map/road_graph.hpp"
#include "map/site.hpp"

namespace fleet::planning::testing {

/// A lattice of roads: nx x ny junction points `pitch` apart, each road sampled every `spacing`,
/// every edge both ways.
inline map::RoadGraph lattice_graph(int nx, int ny, double pitch, double spacing, double x0 = 0.3, double y0 = 0.3) {
  map::RoadGraph g;
  const int per = static_cast<int>(std::lround(pitch / spacing));
  auto add_point = [&](double x, double y) {
    for (const auto& p : g.points) {
      if (std::abs(p.x - x) < 1e-9 && std::abs(p.y - y) < 1e-9) return p.id;
    }
    map::GraphPoint p;
    p.id = static_cast<int>(g.points.size());
    p.x = x;
    p.y = y;
    g.points.push_back(p);
    g.successors.emplace_back();
    return p.id;
  };
  auto link = [&](int a, int b) {
    g.successors[a].push_back(b);
    g.successors[b].push_back(a);
  };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const double x = x0 + i * pitch;
      const double y = y0 + j * pitch;
      if (i + 1 < nx) {
        int prev = add_point(x, y);
        for (int k = 1; k <= per; ++k) {
          const int cur = add_point(x + k * spacing, y);
          link(prev, cur);
          prev = cur;
        }
      }
      if (j + 1 < ny) {
        int prev = add_point(x, y);
        for (int k = 1; k <= per; ++k) {
          const int cur = add_point(x, y + k * spacing);
          link(prev, cur);
          prev = cur;
        }
      }
    }
  }
  return g;
}

inline map::Site site_for(const map::RoadGraph& g, double road_width = 0.3) {
  map::Site s;
  s.name = "test";
  s.road_width = road_width;
  double max_x = 0.0;
  double max_y = 0.0;
  for (const auto& p : g.points) {
    max_x = std::max(max_x, p.x);
    max_y = std::max(max_y, p.y);
  }
  s.bounds = {0.0, 0.0, max_x + 0.3, max_y + 0.3};
  return s;
}

inline geometry::Polygon square(double cx, double cy, double side) {
  const double h = side / 2.0;
  return {{cx - h, cy - h}, {cx + h, cy - h}, {cx + h, cy + h}, {cx - h, cy + h}};
}

}  // namespace fleet::planning::testing
