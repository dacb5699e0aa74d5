// The bodies a vehicle type sweeps through the bends of the roads as its own controller drives
// them, added to the regions of ConflictZones.

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <utility>

#include "sim/tricycle.hpp"
#include "traffic/conflict_zones.hpp"
#include "traffic/vehicle_lanes.hpp"

namespace fleet::traffic {

using geometry::Polygon;
using geometry::Vec2;

namespace {

// A bend starts where the road turns by more than this after a straight stretch, rad (2 degrees:
// a smaller turn swings a 1.7 m body less than 3 cm).
constexpr double kBend = 0.035;
// Road driven at speed before the bend: longer than a pursuit's lookahead, which turns the wheel
// before the bend, metres.
constexpr double kRunUp = 1.6;
// Road driven after the bend's start: through a junction and until the body is straight on its
// lane again, metres.
constexpr double kThrough = 4.5;
// At most this many ways on from one bend (branches within kThrough).
constexpr std::size_t kMaxWays = 8;
// A body on the route, heading along it, within these is covered by the place's own region.
constexpr double kOnRoute = 0.03;      // metres
constexpr double kAlongRoute = 0.035;  // rad

double turn(Vec2 a, Vec2 b, Vec2 c) {
  const Vec2 in = b - a, out = c - b;
  return std::abs(std::atan2(geometry::cross(in, out), geometry::dot(in, out)));
}

// A swept hull's vertices are kept this close to it, metres: the hull, simplified, grows by as much.
constexpr double kSimplify = 0.01;

/// A convex polygon with fewer vertices that holds `hull`: vertices within `tolerance` of the
/// edge that skips them are dropped, and the rest grown by `tolerance`.
Polygon simplified(const Polygon& hull, double tolerance) {
  const std::size_t n = hull.size();
  if (n <= 4) return hull;
  Polygon kept{hull[0]};
  std::size_t anchor = 0;
  for (std::size_t candidate = 2; candidate <= n; ++candidate) {
    const Vec2 a = hull[anchor], b = hull[candidate % n];
    bool within = true;
    for (std::size_t k = anchor + 1; k < candidate && within; ++k) {
      within = geometry::point_segment_distance(hull[k], a, b) <= tolerance;
    }
    if (!within) {
      anchor = candidate - 1;
      kept.push_back(hull[anchor]);
    }
  }
  return kept.size() >= 3 ? grown(kept, tolerance) : hull;
}

}  // namespace

void ConflictZones::add_driven_bodies(const map::RoadGraph& graph, const Polygon& body, std::size_t type) {
  const auto& drive = types_[type].drive;
  const std::size_t places = position_.size();
  // On the lanes the type fits: the others it never drives, and their tight turns it could not
  // follow.
  const PlaceLinks links = place_links(lane_graph_for(graph, footprint_width(types_[type].footprint), params_.margin));
  const auto& next = links.successors;
  const auto& previous = links.predecessors;
  const auto at = [&](int place) { return position_[static_cast<std::size_t>(place)]; };
  // Whether the road runs straight into p and on to q (or starts at p).
  const auto straight_into = [&](int p, int q) {
    const auto& before = previous[static_cast<std::size_t>(p)];
    return before.empty() || std::any_of(before.begin(), before.end(),
                                         [&](int b) { return b != q && turn(at(b), at(p), at(q)) <= kBend; });
  };
  // The run-up: back from p along the straightest road for kRunUp, p last.
  const auto run_up_to = [&](int p, int q) {
    std::vector<int> way{q, p};
    double length = 0.0;
    while (length < kRunUp) {
      const int here = way.back(), after = way[way.size() - 2];
      int best = -1;
      double best_turn = kBend;
      for (int b : previous[static_cast<std::size_t>(here)]) {
        if (std::find(way.begin(), way.end(), b) != way.end()) continue;
        if (const double t = turn(at(b), at(here), at(after)); t <= best_turn) {
          best_turn = t;
          best = b;
        }
      }
      if (best < 0) break;
      length += geometry::distance(at(best), at(here));
      way.push_back(best);
    }
    way.erase(way.begin());
    std::reverse(way.begin(), way.end());
    return way;
  };
  // Every way on from q (q first) for kThrough metres, branching at junctions.
  const auto ways_on = [&](int p, int q) {
    std::vector<std::vector<int>> done;
    std::vector<std::pair<std::vector<int>, double>> open{{{q}, geometry::distance(at(p), at(q))}};
    while (!open.empty() && done.size() < kMaxWays) {
      auto [way, length] = std::move(open.back());
      open.pop_back();
      const int here = way.back();
      const int from = way.size() >= 2 ? way[way.size() - 2] : p;
      bool extended = false;
      if (length < kThrough) {
        for (int n : next[static_cast<std::size_t>(here)]) {
          if (n == from || std::find(way.begin(), way.end(), n) != way.end()) continue;
          std::vector<int> longer = way;
          longer.push_back(n);
          open.emplace_back(std::move(longer), length + geometry::distance(at(here), at(n)));
          extended = true;
        }
      }
      if (!extended) done.push_back(std::move(way));
    }
    return done;
  };
  auto& region = region_[type];
  // The bodies of one drive along `way` off the route, by the place nearest their centres and
  // the places before and after that one on the way (the move they are bodies of).
  std::map<std::tuple<int, int, int>, std::vector<Vec2>> off_route;
  const auto sweep = [&](const std::vector<int>& way, bool at_speed) {
    std::vector<Vec2> path;
    for (int place : way) path.push_back(at(place));
    for (const geometry::Pose2& centre : drive(path, at_speed)) {
      std::size_t nearest = 0;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t k = 0; k < path.size(); ++k) {
        const Vec2 offset = centre.position() - path[k];
        if (const double d = geometry::dot(offset, offset); d < best) {
          best = d;
          nearest = k;
        }
      }
      // On a segment of the route, heading along it: the place's own region holds that body.
      bool covered = false;
      for (std::size_t k = nearest > 0 ? nearest - 1 : 0; k + 1 < path.size() && k <= nearest && !covered; ++k) {
        const Vec2 d = path[k + 1] - path[k];
        covered = geometry::point_segment_distance(centre.position(), path[k], path[k + 1]) <= kOnRoute &&
                  std::abs(geometry::angle_diff(centre.yaw, std::atan2(d.y, d.x))) <= kAlongRoute;
      }
      if (covered) continue;
      const int before = nearest > 0 ? way[nearest - 1] : -1;
      const int after = nearest + 1 < way.size() ? way[nearest + 1] : -1;
      auto& points = off_route[{way[nearest], before, after}];
      const Polygon placed = sim::polygon_in_map(centre, body);
      points.insert(points.end(), placed.begin(), placed.end());
    }
  };
  // One hull per place and way through the bend (a hull over the ways that part there would
  // reach across their fork), unless a polygon the place holds already covers it.
  const auto reserve = [&] {
    for (auto& [move, points] : off_route) {
      const auto [place, before, after] = move;
      auto& polygons = region[static_cast<std::size_t>(place)];
      auto& moves = region_move_[type][static_cast<std::size_t>(place)];
      Polygon hull = simplified(convex_hull(std::move(points)), kSimplify);
      // Held already by a polygon of the same move (or of any move).
      bool inside = false;
      for (std::size_t k = 0; k < polygons.size() && !inside; ++k) {
        const bool same_move =
            (moves[k].before < 0 && moves[k].after < 0) || (moves[k].before == before && moves[k].after == after);
        inside = same_move &&
                 std::all_of(hull.begin(), hull.end(), [&](Vec2 v) { return geometry::contains(polygons[k], v); });
      }
      if (!inside) {
        polygons.push_back(std::move(hull));
        moves.push_back({before, after});
      }
    }
    off_route.clear();
  };
  for (std::size_t qi = 0; qi < places; ++qi) {
    const int q = static_cast<int>(qi);
    for (int p : previous[qi]) {
      if (!straight_into(p, q)) continue;
      for (const std::vector<int>& on : ways_on(p, q)) {
        if (on.size() < 2 || turn(at(p), at(q), at(on[1])) <= kBend) continue;
        // From rest at the place before the bend (a grant's end), and at speed along the road.
        std::vector<int> way{p};
        way.insert(way.end(), on.begin(), on.end());
        sweep(way, false);
        std::vector<int> run = run_up_to(p, q);
        run.insert(run.end(), on.begin(), on.end());
        sweep(run, true);
        reserve();
      }
    }
  }
}

}  // namespace fleet::traffic
