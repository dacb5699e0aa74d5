#include "planning/local_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace fleet::planning {

using geometry::Vec2;

namespace {

bool region_free(const OccupancyGrid& layer, const geometry::Polygon& polygon) {
  const geometry::Bounds b = geometry::bounding_box(polygon);
  const CellIndex lo = layer.cell_of({b.min_x, b.min_y});
  const CellIndex hi = layer.cell_of({b.max_x, b.max_y});
  for (int y = std::max(0, lo.y); y <= std::min(layer.height() - 1, hi.y); ++y) {
    for (int x = std::max(0, lo.x); x <= std::min(layer.width() - 1, hi.x); ++x) {
      if (layer.occupied(x, y) && geometry::contains(polygon, layer.cell_center(x, y))) return false;
    }
  }
  return true;
}

/// The bounding box of the occupied blob holding `p` (searched within `max_extent` of it), at least
/// `min_size` wide: a temporary obstacle covering the whole blob keeps the next plan from touching
/// its edge again.
geometry::Polygon blob_box(const OccupancyGrid& layer, Vec2 p, double min_size, double max_extent) {
  const CellIndex c0 = layer.cell_of(p);
  geometry::Bounds box{p.x - min_size / 2, p.y - min_size / 2, p.x + min_size / 2, p.y + min_size / 2};
  if (!layer.occupied(c0.x, c0.y) || !layer.in_bounds(c0.x, c0.y)) {
    return {{box.min_x, box.min_y}, {box.max_x, box.min_y}, {box.max_x, box.max_y}, {box.min_x, box.max_y}};
  }
  const int reach = static_cast<int>(std::ceil(max_extent / layer.resolution()));
  std::vector<CellIndex> todo{c0};
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(2 * reach + 1) * (2 * reach + 1), 0);
  auto mark = [&](CellIndex c) {
    const int lx = c.x - c0.x + reach;
    const int ly = c.y - c0.y + reach;
    if (lx < 0 || ly < 0 || lx > 2 * reach || ly > 2 * reach) return false;
    std::uint8_t& s = seen[static_cast<std::size_t>(ly) * (2 * reach + 1) + lx];
    if (s) return false;
    s = 1;
    return true;
  };
  mark(c0);
  const double h = layer.resolution() / 2.0;
  while (!todo.empty()) {
    const CellIndex c = todo.back();
    todo.pop_back();
    const Vec2 q = layer.cell_center(c.x, c.y);
    box.min_x = std::min(box.min_x, q.x - h);
    box.min_y = std::min(box.min_y, q.y - h);
    box.max_x = std::max(box.max_x, q.x + h);
    box.max_y = std::max(box.max_y, q.y + h);
    const CellIndex next[4] = {{c.x + 1, c.y}, {c.x - 1, c.y}, {c.x, c.y + 1}, {c.x, c.y - 1}};
    for (const CellIndex& n : next) {
      if (layer.in_bounds(n.x, n.y) && layer.occupied(n.x, n.y) && mark(n)) todo.push_back(n);
    }
  }
  return {{box.min_x, box.min_y}, {box.max_x, box.min_y}, {box.max_x, box.max_y}, {box.min_x, box.max_y}};
}

}  // namespace

LocalPlanner::LocalPlanner(const LocalPlannerConfiguration& configuration, StaticGrid& static_grid,
                           RoadPlanner& road_planner)
    : configuration_(configuration), static_grid_(static_grid), road_planner_(road_planner) {
  if (!(configuration.min_lookahead > 0.0) || configuration.lookahead_time < 0.0) {
    throw std::invalid_argument("local planner: min_lookahead must be > 0 and lookahead_time >= 0");
  }
  if (!(configuration.temporary_size > 0.0)) throw std::invalid_argument("local planner: temporary_size must be > 0");
  if (configuration.clear_cycles < 1) throw std::invalid_argument("local planner: clear_cycles must be >= 1");
}

void LocalPlanner::set_goal(const geometry::Pose2& goal) {
  goal_ = goal;
  dirty_ = true;
}

void LocalPlanner::clear_goal() {
  goal_.reset();
  plan_ = {};
}

void LocalPlanner::replan(const geometry::Pose2& pose) {
  const OccupancyGrid& grid = static_grid_.grid();
  road_planner_.set_obstacles(grid);
  plan_ = road_planner_.plan(pose, *goal_);
  planned_revision_ = static_grid_.revision();
  dirty_ = false;
}

std::optional<std::pair<double, Vec2>> LocalPlanner::first_collision(const geometry::Pose2& pose, double lookahead,
                                                                     const OccupancyGrid& layer) const {
  const auto& pts = plan_.points;
  if (pts.empty()) return std::nullopt;
  // Progress: the plan point nearest the robot; the check starts there.
  std::size_t start = 0;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double d = geometry::distance(pts[i], pose.position());
    if (d < best) {
      best = d;
      start = i;
    }
  }
  const double step = layer.resolution() / 2.0;
  double travelled = 0.0;
  if (layer.occupied_at(pts[start])) return std::make_pair(0.0, pts[start]);
  for (std::size_t i = start + 1; i < pts.size() && travelled < lookahead; ++i) {
    const Vec2 a = pts[i - 1];
    const Vec2 b = pts[i];
    const double len = geometry::distance(a, b);
    const int n = std::max(1, static_cast<int>(std::ceil(len / step)));
    for (int k = 1; k <= n; ++k) {
      const double t = static_cast<double>(k) / n;
      const double along = travelled + t * len;
      if (along > lookahead) return std::nullopt;
      const Vec2 p = a + t * (b - a);
      if (layer.occupied_at(p)) return std::make_pair(along, p);
    }
    travelled += len;
  }
  return std::nullopt;
}

LocalStep LocalPlanner::step(const geometry::Pose2& pose, double speed, const DynamicGrid& dynamic) {
  LocalStep out;
  const OccupancyGrid& layer = dynamic.dynamic_layer();

  // Temporary obstacles whose area is seen free again go, after a few cycles of hysteresis.
  for (auto it = temporaries_.begin(); it != temporaries_.end();) {
    int& free_for = seen_free_[it->first];
    free_for = region_free(layer, it->second) ? free_for + 1 : 0;
    if (free_for >= configuration_.clear_cycles) {
      static_grid_.remove_temporary(it->first);
      out.removed.push_back(it->first);
      seen_free_.erase(it->first);
      it = temporaries_.erase(it);
    } else {
      ++it;
    }
  }
  if (!goal_) {
    out.status = PlanStatus::kNoPath;
    return out;
  }
  if (dirty_ || planned_revision_ != static_grid_.revision()) {
    replan(pose);
    out.replanned = true;
  }

  const double lookahead = std::max(configuration_.min_lookahead, std::abs(speed) * configuration_.lookahead_time);
  auto hit = first_collision(pose, lookahead, layer);
  if (hit) {
    const Vec2 p = hit->second;
    const bool covered = std::any_of(temporaries_.begin(), temporaries_.end(),
                                     [&](const auto& t) { return geometry::contains(t.second, p); });
    if (!covered) {
      // [Forklift thesis, Fig. 5.13]: a temporary static obstacle where the collision is predicted, then a
      // new global plan around it, or up to it when there is no way round.
      const std::string id = configuration_.id_prefix + "-" + std::to_string(next_id_++);
      geometry::Polygon square = blob_box(layer, p, configuration_.temporary_size, configuration_.max_temporary_extent);
      static_grid_.add_temporary(id, square);
      temporaries_[id] = std::move(square);
      seen_free_[id] = 0;
      out.added.push_back(id);
      replan(pose);
      out.replanned = true;
      hit = first_collision(pose, lookahead, layer);
    }
  }
  out.status = plan_.status;
  out.collision_ahead = hit.has_value();
  // Without a plan there is nothing to drive along: no free distance either.
  out.free_distance = plan_.points.empty() ? 0.0 : hit ? hit->first : lookahead;
  return out;
}

}  // namespace fleet::planning
