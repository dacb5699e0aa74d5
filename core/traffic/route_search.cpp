#include "traffic/route_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace fleet::traffic {

RouteSearch::RouteSearch(const map::RoadGraph& graph, const ConflictZones& zones)
    : zones_(zones), successors_(graph.successors) {
  xs_.reserve(graph.points.size());
  ys_.reserve(graph.points.size());
  for (const auto& p : graph.points) {
    xs_.push_back(p.x);
    ys_.push_back(p.y);
  }
  dist_.assign(xs_.size(), 0.0);
  parent_.assign(xs_.size(), -1);
  stamp_.assign(xs_.size(), 0);
}

double RouteSearch::edge_length(int a, int b) const {
  const auto ia = static_cast<std::size_t>(a);
  const auto ib = static_cast<std::size_t>(b);
  return std::hypot(xs_[ib] - xs_[ia], ys_[ib] - ys_[ia]);
}

double RouteSearch::length(const std::vector<int>& route) const {
  double total = 0.0;
  for (std::size_t i = 1; i < route.size(); ++i) total += edge_length(route[i - 1], route[i]);
  return total;
}

std::vector<int> RouteSearch::search(int from, const std::function<bool(int point)>& is_goal,
                                     const std::vector<std::uint8_t>* blocked) {
  if (from < 0 || static_cast<std::size_t>(from) >= xs_.size()) return {};
  if (++query_ == 0) {
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 1;
  }
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  const int start_place = zones_.place_of(from);
  auto seen = [&](int i) { return stamp_[static_cast<std::size_t>(i)] == query_; };
  stamp_[static_cast<std::size_t>(from)] = query_;
  dist_[static_cast<std::size_t>(from)] = 0.0;
  parent_[static_cast<std::size_t>(from)] = -1;
  open.push({0.0, from});
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > dist_[static_cast<std::size_t>(i)]) continue;
    if (is_goal(i)) {
      std::vector<int> route;
      for (int at = i; at >= 0; at = parent_[static_cast<std::size_t>(at)]) route.push_back(at);
      std::reverse(route.begin(), route.end());
      return route;
    }
    for (int j : successors_[static_cast<std::size_t>(i)]) {
      const int place = zones_.place_of(j);
      if (blocked && place != start_place && (*blocked)[static_cast<std::size_t>(place)]) continue;
      const double nd = d + edge_length(i, j);
      if (!seen(j) || nd < dist_[static_cast<std::size_t>(j)]) {
        stamp_[static_cast<std::size_t>(j)] = query_;
        dist_[static_cast<std::size_t>(j)] = nd;
        parent_[static_cast<std::size_t>(j)] = i;
        open.push({nd, j});
      }
    }
  }
  return {};
}

std::vector<int> RouteSearch::shortest(int from, int to, const std::vector<std::uint8_t>* blocked) {
  if (to < 0 || static_cast<std::size_t>(to) >= xs_.size()) return {};
  const int goal_place = zones_.place_of(to);
  return search(from, [&](int point) { return zones_.place_of(point) == goal_place; }, blocked);
}

std::vector<int> RouteSearch::nearest(int from, const std::function<bool(int place)>& accept,
                                      const std::vector<std::uint8_t>* blocked) {
  if (from < 0 || static_cast<std::size_t>(from) >= xs_.size()) return {};
  const int start_place = zones_.place_of(from);
  return search(from, [&](int point) {
    const int place = zones_.place_of(point);
    return place != start_place && accept(place);
  }, blocked);
}

}  // namespace fleet::traffic
