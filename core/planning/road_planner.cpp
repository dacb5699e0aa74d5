#include "planning/road_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace fleet::planning {

using geometry::Vec2;

namespace {

constexpr double kNoHeading = std::numeric_limits<double>::quiet_NaN();

bool heap_less(const auto& a, const auto& b) {
  // Min-heap on f; among equal f the deeper state first, which ends ties towards the goal sooner.
  return a.f > b.f || (a.f == b.f && a.g < b.g);
}

}  // namespace

RoadPlanner::RoadPlanner(const map::RoadGraph& graph, const RoadPlannerConfiguration& configuration)
    : configuration_(configuration) {
  if (configuration.w_d < 0.0 || configuration.w_h < 0.0 || configuration.obstacle_cost < 0.0) {
    // Negative costs would let A* revisit closed states [Forklift thesis, section 5.2].
    throw std::invalid_argument("road planner: w_d, w_h and obstacle_cost must be >= 0");
  }
  if (graph.successors.size() != graph.points.size()) {
    throw std::invalid_argument("road planner: graph has " + std::to_string(graph.points.size()) + " points but " +
                                std::to_string(graph.successors.size()) + " successor lists");
  }
  const std::size_t n = graph.points.size();
  xs_.resize(n);
  ys_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    xs_[i] = graph.points[i].x;
    ys_[i] = graph.points[i].y;
  }
  offsets_.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int j : graph.successors[i]) {
      if (j < 0 || static_cast<std::size_t>(j) >= n) {
        throw std::invalid_argument("road planner: point " + std::to_string(i) + " links to missing point " +
                                    std::to_string(j));
      }
      const double dx = xs_[j] - xs_[i];
      const double dy = ys_[j] - ys_[i];
      targets_.push_back(j);
      edge_length_.push_back(std::hypot(dx, dy));
      edge_angle_.push_back(std::atan2(dy, dx));
    }
    offsets_[i + 1] = static_cast<std::uint32_t>(targets_.size());
  }
  mark_main_component();
  build_index();
  blocked_.assign(n, 0);
  stamp_.assign(n, 0);
  closed_.assign(n, 0);
  g_.assign(n, 0.0);
  heading_.assign(n, kNoHeading);
  parent_.assign(n, -1);
  heap_.reserve(n);
}

void RoadPlanner::set_obstacles(const OccupancyGrid& static_grid) {
  for (std::size_t i = 0; i < xs_.size(); ++i) blocked_[i] = static_grid.occupied_at({xs_[i], ys_[i]}) ? 1 : 0;
}

void RoadPlanner::clear_obstacles() {
  std::fill(blocked_.begin(), blocked_.end(), 0);
}

void RoadPlanner::mark_main_component() {
  // Kosaraju's two passes, iterative: finishing order on the graph, then components on the
  // reversed graph in reverse finishing order.
  const std::size_t n = xs_.size();
  std::vector<std::uint32_t> rev_offsets(n + 1, 0);
  for (int t : targets_) ++rev_offsets[static_cast<std::size_t>(t) + 1];
  for (std::size_t i = 0; i < n; ++i) rev_offsets[i + 1] += rev_offsets[i];
  std::vector<int> rev_targets(targets_.size());
  std::vector<std::uint32_t> fill(rev_offsets.begin(), rev_offsets.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::uint32_t e = offsets_[i]; e < offsets_[i + 1]; ++e)
      rev_targets[fill[targets_[e]]++] = static_cast<int>(i);
  }
  std::vector<int> order;
  order.reserve(n);
  std::vector<std::uint8_t> visited(n, 0);
  std::vector<std::pair<int, std::uint32_t>> stack;
  for (std::size_t root = 0; root < n; ++root) {
    if (visited[root]) continue;
    visited[root] = 1;
    stack.push_back({static_cast<int>(root), offsets_[root]});
    while (!stack.empty()) {
      auto& [u, next] = stack.back();
      if (next < offsets_[u + 1]) {
        const int v = targets_[next++];
        if (!visited[v]) {
          visited[v] = 1;
          stack.push_back({v, offsets_[v]});
        }
      } else {
        order.push_back(u);
        stack.pop_back();
      }
    }
  }
  std::vector<int> component(n, -1);
  std::vector<std::size_t> sizes;
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    if (component[*it] >= 0) continue;
    const int id = static_cast<int>(sizes.size());
    sizes.push_back(0);
    std::vector<int> todo{*it};
    component[*it] = id;
    while (!todo.empty()) {
      const int u = todo.back();
      todo.pop_back();
      ++sizes.back();
      for (std::uint32_t e = rev_offsets[u]; e < rev_offsets[u + 1]; ++e) {
        const int v = rev_targets[e];
        if (component[v] < 0) {
          component[v] = id;
          todo.push_back(v);
        }
      }
    }
  }
  main_component_.assign(n, 0);
  if (sizes.empty()) return;
  const int main = static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  for (std::size_t i = 0; i < n; ++i) main_component_[i] = component[i] == main ? 1 : 0;
}

void RoadPlanner::build_index() {
  if (xs_.empty()) return;
  const auto [min_x, max_x] = std::minmax_element(xs_.begin(), xs_.end());
  const auto [min_y, max_y] = std::minmax_element(ys_.begin(), ys_.end());
  index_min_x_ = *min_x;
  index_min_y_ = *min_y;
  index_nx_ = static_cast<int>((*max_x - *min_x) / kIndexCell) + 1;
  index_ny_ = static_cast<int>((*max_y - *min_y) / kIndexCell) + 1;
  const auto cell_of = [&](std::size_t i) {
    const int cx = std::min(index_nx_ - 1, static_cast<int>((xs_[i] - index_min_x_) / kIndexCell));
    const int cy = std::min(index_ny_ - 1, static_cast<int>((ys_[i] - index_min_y_) / kIndexCell));
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(index_nx_) + static_cast<std::size_t>(cx);
  };
  cell_start_.assign(static_cast<std::size_t>(index_nx_) * static_cast<std::size_t>(index_ny_) + 1, 0);
  for (std::size_t i = 0; i < xs_.size(); ++i) ++cell_start_[cell_of(i) + 1];
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  cell_points_.resize(xs_.size());
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < xs_.size(); ++i) cell_points_[fill[cell_of(i)]++] = static_cast<int>(i);
}

int RoadPlanner::nearest_point(Vec2 p, PointUse use) const {
  const double fx = (p.x - index_min_x_) / kIndexCell;
  const double fy = (p.y - index_min_y_) / kIndexCell;
  // Off the indexed area (or not a number) the plain scan answers.
  if (!(fx >= 0.0 && fy >= 0.0 && fx < index_nx_ && fy < index_ny_)) return nearest_point_scan(p, use);
  const int cx = static_cast<int>(fx);
  const int cy = static_cast<int>(fy);
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  const auto visit = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= index_nx_ || y >= index_ny_) return;
    const std::size_t c =
        static_cast<std::size_t>(y) * static_cast<std::size_t>(index_nx_) + static_cast<std::size_t>(x);
    for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      const int i = cell_points_[k];
      if (use == PointUse::kRoute && !main_component_[static_cast<std::size_t>(i)]) continue;
      const double dx = xs_[static_cast<std::size_t>(i)] - p.x;
      const double dy = ys_[static_cast<std::size_t>(i)] - p.y;
      const double d2 = dx * dx + dy * dy;
      // Ties go to the lower id, as in the scan.
      if (d2 < best_d2 || (d2 == best_d2 && i < best)) {
        best_d2 = d2;
        best = i;
      }
    }
  };
  const int rings = std::max(index_nx_, index_ny_);
  for (int r = 0; r <= rings; ++r) {
    if (r == 0) {
      visit(cx, cy);
    } else {
      for (int x = cx - r; x <= cx + r; ++x) {
        visit(x, cy - r);
        visit(x, cy + r);
      }
      for (int y = cy - r + 1; y <= cy + r - 1; ++y) {
        visit(cx - r, y);
        visit(cx + r, y);
      }
    }
    // Every point of ring r + 1 is at least r cells away from p.
    const double reach = r * kIndexCell;
    if (best >= 0 && best_d2 <= reach * reach) break;
  }
  return best;
}

int RoadPlanner::nearest_point_scan(Vec2 p, PointUse use) const {
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < xs_.size(); ++i) {
    if (use == PointUse::kRoute && !main_component_[i]) continue;
    const double dx = xs_[i] - p.x;
    const double dy = ys_[i] - p.y;
    const double d2 = dx * dx + dy * dy;
    if (d2 < best_d2) {
      best_d2 = d2;
      best = static_cast<int>(i);
    }
  }
  return best;
}

int RoadPlanner::nearest_point_along(Vec2 p, double heading, double tolerance) const {
  int best = -1;
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < xs_.size(); ++i) {
    if (!main_component_[i]) continue;
    const double dx = xs_[i] - p.x;
    const double dy = ys_[i] - p.y;
    const double d2 = dx * dx + dy * dy;
    if (d2 >= best_d2) continue;
    for (std::uint32_t e = offsets_[i]; e < offsets_[i + 1]; ++e) {
      const double off = std::abs(geometry::angle_diff(edge_angle_[e], heading));
      if (std::min(off, std::numbers::pi - off) <= tolerance) {
        best_d2 = d2;
        best = static_cast<int>(i);
        break;
      }
    }
  }
  return best;
}

RoadPlan RoadPlanner::plan(const geometry::Pose2& start, const geometry::Pose2& goal, const PlanOptions& options) {
  // [Forklift thesis, Fig. 5.6]: the states nearest the poses; C(x_S) is the distance to the start state.
  const int s = nearest_point(start.position(), PointUse::kRoute);
  const int g = nearest_point(goal.position(), PointUse::kRoute);
  if (s < 0 || g < 0) {
    RoadPlan empty;
    empty.status = PlanStatus::kInvalidStart;
    return empty;
  }
  return plan_between(s, g, geometry::distance(start.position(), {xs_[s], ys_[s]}), options);
}

std::vector<std::pair<int, double>> RoadPlanner::start_states(Vec2 p, double slack) const {
  std::vector<std::pair<int, double>> states;
  const int nearest = nearest_point(p, PointUse::kRoute);
  if (nearest < 0) return states;
  const double nearest_distance = std::hypot(xs_[nearest] - p.x, ys_[nearest] - p.y);
  const double within = slack * nearest_distance;
  states.emplace_back(nearest, nearest_distance);
  for (std::uint32_t e = offsets_[nearest]; e < offsets_[nearest + 1]; ++e) {
    const int next = targets_[e];
    const double d = std::hypot(xs_[next] - p.x, ys_[next] - p.y);
    if (main_component_[next] && d <= within) states.emplace_back(next, d);
  }
  return states;
}

RoadPlan RoadPlanner::plan_between(int start_point, int goal_point, double start_cost, const PlanOptions& options) {
  return plan_from({{start_point, start_cost}}, goal_point, options);
}

RoadPlan RoadPlanner::plan_from(const std::vector<std::pair<int, double>>& starts, int goal_point,
                                const PlanOptions& options) {
  RoadPlan result;
  const int n = static_cast<int>(xs_.size());
  const bool starts_valid = !starts.empty() && std::all_of(starts.begin(), starts.end(),
                                                           [&](const auto& s) { return s.first >= 0 && s.first < n; });
  if (!starts_valid || goal_point < 0 || goal_point >= n) {
    result.status = PlanStatus::kInvalidStart;
    return result;
  }
  const Deadline deadline(options);
  if (++query_ == 0) {  // wrapped: every stamp is stale again
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 1;
  }
  const double gx = xs_[goal_point];
  const double gy = ys_[goal_point];
  const double w_d = configuration_.w_d;
  const double w_h = configuration_.w_h;
  const double obs = configuration_.obstacle_cost;
  // Euclidean heuristic (Forklift thesis, Fig. 5.7, 5.8), scaled by w_d so it never overestimates eq. 5.5.
  auto h = [&](int i) { return w_d * std::hypot(xs_[i] - gx, ys_[i] - gy); };
  auto touch = [&](int i) {
    if (stamp_[i] != query_) {
      stamp_[i] = query_;
      closed_[i] = 0;
      parent_[i] = -1;
      heading_[i] = kNoHeading;
      g_[i] = std::numeric_limits<double>::infinity();
    }
  };

  heap_.clear();
  for (const auto& [start_point, start_cost] : starts) {
    touch(start_point);
    if (start_cost >= g_[start_point]) continue;
    g_[start_point] = start_cost;  // C(x_S); a start state has no heading
    heap_.push_back({start_cost + h(start_point), start_cost, start_point});
    std::push_heap(heap_.begin(), heap_.end(), [](const HeapItem& a, const HeapItem& b) { return heap_less(a, b); });
  }
  bool found = false;
  std::size_t iterations = 0;
  while (!heap_.empty()) {
    if ((iterations++ & 63) == 0) {
      const PlanStatus st = deadline.check();
      if (st != PlanStatus::kFound) {
        result.status = st;
        return result;
      }
    }
    std::pop_heap(heap_.begin(), heap_.end(), [](const HeapItem& a, const HeapItem& b) { return heap_less(a, b); });
    const HeapItem item = heap_.back();
    heap_.pop_back();
    const int x = item.node;
    if (closed_[x] || item.g > g_[x]) continue;  // a stale copy: the state was improved since
    closed_[x] = 1;
    ++result.expanded;
    if (x == goal_point) {
      found = true;
      break;
    }
    if (result.expanded > options.node_cap) {
      result.status = PlanStatus::kTimeout;
      return result;
    }
    const double h1 = heading_[x];
    for (std::uint32_t e = offsets_[x]; e < offsets_[x + 1]; ++e) {
      const int y = targets_[e];
      touch(y);
      if (closed_[y]) continue;
      // [Forklift thesis, eq. 5.5]: C(x1, x2) = w_d * Euc + w_h * |norm(h1 - atan2(dy, dx))|; no heading
      // cost out of a state without an assigned heading.
      double c = w_d * edge_length_[e];
      if (!std::isnan(h1)) c += w_h * std::abs(geometry::normalize_angle(h1 - edge_angle_[e]));
      if (blocked_[y]) c += obs;  // Obs(x'), section 5.3
      const double g_new = g_[x] + c;
      if (g_new < g_[y]) {
        g_[y] = g_new;
        parent_[y] = x;
        heading_[y] = edge_angle_[e];  // the heading assigned from the parent
        heap_.push_back({g_new + h(y), g_new, y});
        std::push_heap(heap_.begin(), heap_.end(),
                       [](const HeapItem& a, const HeapItem& b) { return heap_less(a, b); });
      }
    }
  }
  if (!found) {
    result.status = PlanStatus::kNoPath;
    return result;
  }
  for (int v = goal_point; v != -1; v = parent_[v]) result.point_ids.push_back(v);
  std::reverse(result.point_ids.begin(), result.point_ids.end());
  result.cost = g_[goal_point];
  result.status = PlanStatus::kFound;

  // [Forklift thesis, Fig. 5.11]: a route through an obstacle is kept only up to the obstacle, so the robot
  // waits at the last free point and goes on once the obstacle is removed. A start already inside
  // an obstacle is left behind first: the robot may drive out of it.
  std::size_t first = 0;
  while (first < result.point_ids.size() && blocked_[result.point_ids[first]]) ++first;
  for (std::size_t k = std::max<std::size_t>(first, 1); k < result.point_ids.size(); ++k) {
    if (blocked_[result.point_ids[k]]) {
      result.blocked_point = result.point_ids[k];
      result.point_ids.resize(k);
      result.status = PlanStatus::kBlockedPartial;
      break;
    }
  }
  result.points.reserve(result.point_ids.size());
  for (std::size_t k = 0; k < result.point_ids.size(); ++k) {
    const int v = result.point_ids[k];
    result.points.push_back({xs_[v], ys_[v]});
    if (k > 0) result.length += geometry::distance(result.points[k - 1], result.points[k]);
  }
  return result;
}

}  // namespace fleet::planning
