#include "planning/static_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fleet::planning {

using geometry::Polygon;
using geometry::Vec2;

namespace {

Polygon rectangle_along(Vec2 a, Vec2 b, double width) {
  const Vec2 d = b - a;
  const double len = geometry::norm(d);
  const Vec2 u = len > 1e-12 ? (1.0 / len) * d : Vec2{1.0, 0.0};
  const Vec2 n{-u.y * width / 2.0, u.x * width / 2.0};
  return {a - n, b - n, b + n, a + n};
}

}  // namespace

StaticGrid::StaticGrid(const StaticGridConfiguration& configuration, const map::Site& site, const map::RoadGraph& graph)
    : configuration_(configuration),
      road_width_(configuration.road_width > 0.0 ? configuration.road_width : site.road_width),
      map_layer_(site.bounds, configuration.resolution, OccupancyGrid::kOccupied) {
  if (!(road_width_ > 0.0)) throw std::invalid_argument("static grid: road_width must be positive");
  if (configuration.obstacle_inflation < 0.0)
    throw std::invalid_argument("static grid: obstacle_inflation must be >= 0");
  // "Setting the values of map points with a square of side equal to road width" [Forklift thesis,
  // section 5.3]; the points are close enough that the squares join into roads (Forklift thesis, Fig. 5.9a).
  const double h = road_width_ / 2.0;
  for (const auto& p : graph.points) {
    map_layer_.fill_polygon({{p.x - h, p.y - h}, {p.x + h, p.y - h}, {p.x + h, p.y + h}, {p.x - h, p.y + h}}, false);
  }
  // Loading areas sit beside the roads (Forklift thesis, Fig. 5.1): free a square on the area and a corridor to the
  // nearest graph point, so the grid planner can leave the road to pick or drop.
  const double w = configuration.loading_area_width > 0.0 ? configuration.loading_area_width : road_width_;
  // Homes are parking places beside the roads as well: free them the same way.
  std::vector<Vec2> places;
  for (const auto& area : site.loading_areas) places.push_back(area.pose.position());
  for (const auto& home : site.homes) places.push_back(home.pose.position());
  for (const Vec2 c : places) {
    map_layer_.fill_polygon({{c.x - w / 2, c.y - w / 2},
                             {c.x + w / 2, c.y - w / 2},
                             {c.x + w / 2, c.y + w / 2},
                             {c.x - w / 2, c.y + w / 2}},
                            false);
    double best = std::numeric_limits<double>::infinity();
    Vec2 nearest = c;
    for (const auto& p : graph.points) {
      const double d = geometry::distance(c, {p.x, p.y});
      if (d < best) {
        best = d;
        nearest = {p.x, p.y};
      }
    }
    if (std::isfinite(best)) map_layer_.fill_polygon(rectangle_along(c, nearest, w), false);
  }
  for (const auto& o : site.static_obstacles) {
    site_obstacles_[o.id] = o.polygon;
    if (o.enabled_at_start) enabled_.insert(o.id);
  }
}

bool StaticGrid::set_obstacle_enabled(const std::string& id, bool enabled) {
  if (!site_obstacles_.contains(id)) return false;
  const bool changed = enabled ? enabled_.insert(id).second : enabled_.erase(id) > 0;
  if (changed) ++revision_;
  return true;
}

void StaticGrid::add_obstacle(const std::string& id, const Polygon& polygon) {
  extra_obstacles_[id] = polygon;
  ++revision_;
}

bool StaticGrid::remove_obstacle(const std::string& id) {
  if (extra_obstacles_.erase(id) == 0) return false;
  ++revision_;
  return true;
}

void StaticGrid::add_temporary(const std::string& id, const Polygon& polygon) {
  temporaries_[id] = polygon;
  ++revision_;
}

bool StaticGrid::remove_temporary(const std::string& id) {
  if (temporaries_.erase(id) == 0) return false;
  ++revision_;
  return true;
}

const OccupancyGrid& StaticGrid::grid() {
  if (built_revision_ != revision_) rebuild();
  return grid_;
}

const OccupancyGrid& StaticGrid::permanent_grid() {
  if (built_revision_ != revision_) rebuild();
  return permanent_;
}

void StaticGrid::stamp(OccupancyGrid& grid, const Polygon& polygon) const {
  if (configuration_.obstacle_inflation <= 0.0) {
    grid.fill_polygon(polygon, true);
    return;
  }
  // Grow the polygon by a disc: fill it, then run discs along its edges (a Minkowski sum that
  // stays exact for concave polygons too).
  grid.fill_polygon(polygon, true);
  const double r = configuration_.obstacle_inflation;
  const double step = grid.resolution() / 2.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2 a = polygon[i];
    const Vec2 b = polygon[(i + 1) % polygon.size()];
    const double len = geometry::distance(a, b);
    const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
    for (int k = 0; k <= n; ++k) grid.fill_disc(a + (static_cast<double>(k) / n) * (b - a), r, true);
  }
}

void StaticGrid::rebuild() {
  permanent_ = map_layer_;
  for (const auto& id : enabled_) stamp(permanent_, site_obstacles_.at(id));
  for (const auto& [id, polygon] : extra_obstacles_) stamp(permanent_, polygon);
  grid_ = permanent_;
  for (const auto& [id, polygon] : temporaries_) stamp(grid_, polygon);
  built_revision_ = revision_;
  ++build_count_;
}

}  // namespace fleet::planning
