#include "traffic/conflict_zones.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "geometry/convex_hull.hpp"
#include "sim/tricycle.hpp"

namespace fleet::traffic {

using geometry::Polygon;
using geometry::Vec2;

geometry::Polygon convex_hull(std::vector<Vec2> points) {
  return geometry::convex_hull(std::move(points));
}

geometry::Polygon rectangle_footprint(const geometry::Footprint& footprint) {
  const double hl = footprint.length / 2.0;
  const double hw = footprint.width / 2.0;
  return {{hl, hw}, {-hl, hw}, {-hl, -hw}, {hl, -hw}};
}

namespace {

/// Extent of a footprint along one of the body's axes.
double extent(const geometry::Polygon& footprint, double Vec2::*axis) {
  if (footprint.empty()) return 0.0;
  double lo = footprint.front().*axis, hi = lo;
  for (const Vec2& v : footprint) {
    lo = std::min(lo, v.*axis);
    hi = std::max(hi, v.*axis);
  }
  return hi - lo;
}

}  // namespace

double footprint_width(const geometry::Polygon& footprint) {
  return extent(footprint, &Vec2::y);
}

double footprint_length(const geometry::Polygon& footprint) {
  return extent(footprint, &Vec2::x);
}

namespace {

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

bool boxes_overlap(const geometry::Bounds& a, const geometry::Bounds& b) {
  return a.min_x <= b.max_x && b.min_x <= a.max_x && a.min_y <= b.max_y && b.min_y <= a.max_y;
}

// A region's polygons with their bounding boxes: a place that reserves a swept turn holds many
// polygons, most of them far from a given one of another place's.
struct BoxedRegion {
  const std::vector<Polygon>* polygons = nullptr;
  std::vector<geometry::Bounds> boxes;
};

std::vector<BoxedRegion> boxed(const std::vector<std::vector<Polygon>>& regions) {
  std::vector<BoxedRegion> out(regions.size());
  for (std::size_t p = 0; p < regions.size(); ++p) {
    out[p].polygons = &regions[p];
    for (const Polygon& polygon : regions[p]) out[p].boxes.push_back(geometry::bounding_box(polygon));
  }
  return out;
}

bool regions_overlap(const BoxedRegion& a, const BoxedRegion& b) {
  for (std::size_t i = 0; i < a.boxes.size(); ++i) {
    for (std::size_t k = 0; k < b.boxes.size(); ++k) {
      if (boxes_overlap(a.boxes[i], b.boxes[k]) &&
          geometry::convex_polygons_overlap((*a.polygons)[i], (*b.polygons)[k]))
        return true;
    }
  }
  return false;
}

}  // namespace

Polygon grown(const Polygon& convex, double grow) {
  const std::size_t n = convex.size();
  std::vector<Vec2> normal(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e = convex[(i + 1) % n] - convex[i];
    const double length = geometry::norm(e);
    normal[i] = {e.y / length, -e.x / length};
  }
  Polygon out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = normal[(i + n - 1) % n];
    const Vec2 b = normal[i];
    out[i] = convex[i] + (grow / (1.0 + geometry::dot(a, b))) * (a + b);
  }
  return out;
}

ConflictZones::ConflictZones(const map::RoadGraph& graph, const ResourceParams& params) : params_(params) {
  if (!(params.margin >= 0.0)) {
    throw std::invalid_argument("traffic ResourceParams: margin must be >= 0 (margin=" + std::to_string(params.margin) +
                                ")");
  }
  types_ = params.vehicle_types;
  if (types_.empty()) {
    if (!(params.footprint.length > 0.0) || !(params.footprint.width > 0.0)) {
      throw std::invalid_argument("traffic ResourceParams: footprint length and width must be > 0 (length=" +
                                  std::to_string(params.footprint.length) +
                                  ", width=" + std::to_string(params.footprint.width) + ")");
    }
    types_.push_back({"default", rectangle_footprint(params.footprint)});
  }
  for (const VehicleType& type : types_) {
    if (geometry::convex_hull(type.footprint).size() < 3) {
      throw std::invalid_argument("traffic vehicle type '" + type.name +
                                  "': the footprint needs three corners not on one line");
    }
  }
  const std::size_t n = graph.points.size();
  if (graph.successors.size() != n)
    throw std::invalid_argument("traffic ConflictZones: successors size differs from points size");

  // Undirected point adjacency.
  std::vector<std::vector<int>> adjacent(n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int j : graph.successors[i]) {
      if (j < 0 || static_cast<std::size_t>(j) >= n)
        throw std::invalid_argument("traffic ConflictZones: edge to unknown point");
      adjacent[i].push_back(j);
      adjacent[static_cast<std::size_t>(j)].push_back(static_cast<int>(i));
    }
  }
  for (auto& a : adjacent) {
    std::sort(a.begin(), a.end());
    a.erase(std::unique(a.begin(), a.end()), a.end());
  }
  std::vector<std::vector<int>> members;
  build_places(graph, members);

  // Place adjacency.
  const std::size_t places = members.size();
  neighbours_.assign(places, {});
  for (std::size_t p = 0; p < places; ++p) {
    for (int i : members[p]) {
      for (int j : adjacent[static_cast<std::size_t>(i)]) {
        const int q = place_of_[static_cast<std::size_t>(j)];
        if (static_cast<std::size_t>(q) != p) neighbours_[p].push_back(q);
      }
    }
    std::sort(neighbours_[p].begin(), neighbours_[p].end());
    neighbours_[p].erase(std::unique(neighbours_[p].begin(), neighbours_[p].end()), neighbours_[p].end());
  }

  const std::size_t types = types_.size();
  region_.assign(types, {});
  region_move_.assign(types, {});
  reach_.assign(types, {});
  for (std::size_t t = 0; t < types; ++t) build_regions(graph, adjacent, members, t);
  conflicts_.assign(types * types, {});
  for (std::size_t a = 0; a < types; ++a) {
    for (std::size_t b = a; b < types; ++b) build_conflicts(a, b);
  }
  branch_.assign(places, 0);
  for (std::size_t p = 0; p < places; ++p) branch_[p] = neighbours_[p].size() >= 3 ? 1 : 0;
  build_corridors();
  // Directed place adjacency: which branch places every way through passes one corridor.
  const PlaceLinks links = place_links(graph);
  build_stoppable(links.successors, links.predecessors);
  // What a type's own drive sweeps through the bends joins its regions after stoppability: a
  // robot may wait where a turning one would sweep, as traffic never grants the turn while it
  // stands there (the places conflict), and a tight turn a type could take but never does would
  // otherwise keep everyone from waiting on the lanes beside it.
  std::vector<std::uint8_t> driven(types, 0);
  for (std::size_t t = 0; t < types; ++t) {
    if (!types_[t].drive) continue;
    driven[t] = 1;
    add_driven_bodies(graph, grown(geometry::convex_hull(types_[t].footprint), params_.margin / 2.0), t);
    update_reach(t);
  }
  for (std::size_t a = 0; a < types; ++a) {
    for (std::size_t b = a; b < types; ++b) {
      if (driven[a] || driven[b]) build_conflicts(a, b);
    }
  }
  build_opposite_lanes(graph, members);
}

ConflictZones::PlaceLinks ConflictZones::place_links(const map::RoadGraph& graph) const {
  const std::size_t places = position_.size();
  PlaceLinks links{std::vector<std::vector<int>>(places), std::vector<std::vector<int>>(places)};
  for (std::size_t i = 0; i < graph.points.size(); ++i) {
    const int a = place_of_[i];
    for (int j : graph.successors[i]) {
      const int b = place_of_[static_cast<std::size_t>(j)];
      if (a == b) continue;
      links.successors[static_cast<std::size_t>(a)].push_back(b);
      links.predecessors[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  for (auto* list : {&links.successors, &links.predecessors}) {
    for (auto& l : *list) {
      std::sort(l.begin(), l.end());
      l.erase(std::unique(l.begin(), l.end()), l.end());
    }
  }
  return links;
}

void ConflictZones::build_places(const map::RoadGraph& graph, std::vector<std::vector<int>>& members) {
  // Places: points joined by (near) zero-length edges or lying on top of each other. A sweep along
  // x finds coincident points that no edge joins.
  const std::size_t n = graph.points.size();
  auto pos = [&](std::size_t i) { return Vec2{graph.points[i].x, graph.points[i].y}; };
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto unite = [&](int a, int b) {
    a = find_root(parent, a);
    b = find_root(parent, b);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  };
  std::vector<int> by_x(n);
  std::iota(by_x.begin(), by_x.end(), 0);
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) {
    return graph.points[static_cast<std::size_t>(a)].x < graph.points[static_cast<std::size_t>(b)].x;
  });
  const double eps = params_.coincident_distance;
  for (std::size_t a = 0; a < n; ++a) {
    const auto ia = static_cast<std::size_t>(by_x[a]);
    for (std::size_t b = a + 1; b < n; ++b) {
      const auto ib = static_cast<std::size_t>(by_x[b]);
      if (graph.points[ib].x - graph.points[ia].x > eps) break;
      if (geometry::distance(pos(ia), pos(ib)) <= eps) unite(by_x[a], by_x[b]);
    }
  }
  place_of_.assign(n, -1);
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
}

void ConflictZones::build_regions(const map::RoadGraph& graph, const std::vector<std::vector<int>>& adjacent,
                                  const std::vector<std::vector<int>>& members, std::size_t type) {
  const std::size_t places = members.size();
  const Polygon body = grown(geometry::convex_hull(types_[type].footprint), params_.margin / 2.0);
  const double tracking_x = types_[type].tracking_x;
  auto pos = [&](std::size_t i) { return Vec2{graph.points[i].x, graph.points[i].y}; };
  auto& region = region_[type];
  auto& moves = region_move_[type];
  auto& reach = reach_[type];
  region.assign(places, {});
  moves.assign(places, {});
  reach.assign(places, 0.0);
  for (std::size_t p = 0; p < places; ++p) {
    for (int i : members[p]) {
      for (int j : adjacent[static_cast<std::size_t>(i)]) {
        if (static_cast<std::size_t>(place_of_[static_cast<std::size_t>(j)]) == p) continue;
        const Vec2 a = pos(static_cast<std::size_t>(i));
        const Vec2 b = pos(static_cast<std::size_t>(j));
        const double heading = std::atan2(b.y - a.y, b.x - a.x);
        const Vec2 mid = 0.5 * (a + b);
        Polygon corners = sim::polygon_in_map({a.x, a.y, heading}, body);
        const Polygon far = sim::polygon_in_map({mid.x, mid.y, heading}, body);
        corners.insert(corners.end(), far.begin(), far.end());
        region[p].push_back(geometry::convex_hull(std::move(corners)));
        const int other = place_of_[static_cast<std::size_t>(j)];
        moves[p].push_back({other, other});
      }
    }
    if (region[p].empty()) {
      // An isolated place: the robot may stand there at any heading.
      const Vec2 a = position_[p];
      for (double heading : {0.0, std::acos(0.0)}) {
        region[p].push_back(sim::polygon_in_map({a.x, a.y, heading}, body));
        moves[p].push_back({});
      }
    }
  }
  if (tracking_x != 0.0) add_tracked_bodies(graph, adjacent, body, -tracking_x, type);
  update_reach(type);
}

bool ConflictZones::body_reaches_move(const Polygon& body, int type, int from, int to) const {
  if (body.empty() || !may_reach(geometry::bounding_circle(body), type, to)) return false;
  const auto& polygons = region(type, to);
  const auto& moves = region_moves(type, to);
  for (std::size_t k = 0; k < polygons.size(); ++k) {
    const bool of_move = moves[k].before < 0 || moves[k].before == from;
    if (of_move && geometry::convex_polygons_overlap(body, polygons[k])) return true;
  }
  return false;
}

bool ConflictZones::may_reach(const geometry::BoundingCircle& body, int type, int place) const {
  const Vec2 at = position(place);
  const double dx = body.centre.x - at.x;
  const double dy = body.centre.y - at.y;
  const double apart = body.radius + reach(type, place);
  return dx * dx + dy * dy <= apart * apart;
}

void ConflictZones::update_reach(std::size_t type) {
  auto& reach = reach_[type];
  for (std::size_t p = 0; p < position_.size(); ++p) {
    for (const Polygon& poly : region_[type][p]) {
      for (const Vec2& v : poly) reach[p] = std::max(reach[p], geometry::distance(v, position_[p]));
    }
  }
}

void ConflictZones::add_tracked_bodies(const map::RoadGraph& graph, const std::vector<std::vector<int>>& adjacent,
                                       const Polygon& body, double lead, std::size_t type) {
  // A body steered by a point `lead` metres behind its centre (a tricycle's rear axle) has that
  // point on the route and its centre `lead` ahead along the heading there. On a straight road
  // that is the centred body a little further on; in a curve the centre leaves the route on the
  // outside and the front swings wide. Each such body is added to the place of the route point
  // nearest its centre, searched forward along the road, where the robot's progress puts it.
  constexpr double kOnRoute = 0.05;  // metres
  auto pos = [&](int i) {
    const auto& point = graph.points[static_cast<std::size_t>(i)];
    return Vec2{point.x, point.y};
  };
  auto& region = region_[type];
  const std::size_t n = graph.points.size();
  std::vector<std::pair<int, Polygon>> tracked;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = pos(static_cast<int>(i));
    for (int j : adjacent[i]) {
      const Vec2 b = pos(j);
      const double heading = std::atan2(b.y - a.y, b.x - a.x);
      const Vec2 centre = a + lead * Vec2{std::cos(heading), std::sin(heading)};
      // Forward from a through b, never turning back by more than a right angle, up to twice
      // the lead along the road.
      int nearest = j;
      double best = geometry::distance(centre, b);
      // How far the centre is off the road: on it, the regions of the edge's two ends cover the
      // body already.
      double off_road = geometry::point_segment_distance(centre, a, b);
      struct Step {
        int from, at;
        double travelled;
      };
      std::vector<Step> open{{static_cast<int>(i), j, geometry::distance(a, b)}};
      while (!open.empty()) {
        const Step s = open.back();
        open.pop_back();
        const Vec2 from = pos(s.from), at = pos(s.at);
        for (int k : adjacent[static_cast<std::size_t>(s.at)]) {
          if (k == s.from) continue;
          const Vec2 next = pos(k);
          if ((at.x - from.x) * (next.x - at.x) + (at.y - from.y) * (next.y - at.y) <= 0.0) continue;
          const double travelled = s.travelled + geometry::distance(at, next);
          if (travelled > 2.0 * lead) continue;
          off_road = std::min(off_road, geometry::point_segment_distance(centre, at, next));
          if (const double d = geometry::distance(centre, next); d < best) {
            best = d;
            nearest = k;
          }
          open.push_back({s.at, k, travelled});
        }
      }
      if (off_road < kOnRoute) continue;
      tracked.emplace_back(place_of_[static_cast<std::size_t>(nearest)],
                           sim::polygon_in_map({centre.x, centre.y, heading}, body));
    }
  }
  for (auto& [place, polygon] : tracked) {
    region[static_cast<std::size_t>(place)].push_back(std::move(polygon));
    region_move_[type][static_cast<std::size_t>(place)].push_back({});
  }
}

void ConflictZones::build_conflicts(std::size_t type_a, std::size_t type_b) {
  // (type_a at p, type_b at q) and its mirror (type_b at p, type_a at q). A sweep along x bounds
  // the candidate pairs by the largest region reach of either type.
  const std::size_t places = position_.size();
  auto& ab = conflicts_[pair_index(static_cast<int>(type_a), static_cast<int>(type_b))];
  auto& ba = conflicts_[pair_index(static_cast<int>(type_b), static_cast<int>(type_a))];
  const bool same = type_a == type_b;
  ab.assign(places, {});
  if (!same) ba.assign(places, {});
  const auto& reach_a = reach_[type_a];
  const auto& reach_b = reach_[type_b];
  const std::vector<BoxedRegion> region_a = boxed(region_[type_a]);
  const std::vector<BoxedRegion> region_b = boxed(region_[type_b]);
  double max_reach = 0.0;
  for (std::size_t p = 0; p < places; ++p) max_reach = std::max({max_reach, reach_a[p], reach_b[p]});
  std::vector<int> order(places);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return position_[static_cast<std::size_t>(a)].x < position_[static_cast<std::size_t>(b)].x;
  });
  for (std::size_t a = 0; a < places; ++a) {
    const auto pa = static_cast<std::size_t>(order[a]);
    ab[pa].push_back(static_cast<int>(pa));
    if (!same) ba[pa].push_back(static_cast<int>(pa));
    const double reach_pa = std::max(reach_a[pa], reach_b[pa]);
    for (std::size_t b = a + 1; b < places; ++b) {
      const auto pb = static_cast<std::size_t>(order[b]);
      if (position_[pb].x - position_[pa].x > reach_pa + max_reach) break;
      const double d = geometry::distance(position_[pa], position_[pb]);
      if (d <= reach_a[pa] + reach_b[pb] && regions_overlap(region_a[pa], region_b[pb])) {
        ab[pa].push_back(static_cast<int>(pb));
        (same ? ab : ba)[pb].push_back(static_cast<int>(pa));
      }
      if (!same && d <= reach_b[pa] + reach_a[pb] && regions_overlap(region_b[pa], region_a[pb])) {
        ba[pa].push_back(static_cast<int>(pb));
        ab[pb].push_back(static_cast<int>(pa));
      }
    }
  }
  for (auto& c : ab) std::sort(c.begin(), c.end());
  if (!same) {
    for (auto& c : ba) std::sort(c.begin(), c.end());
  }
}

void ConflictZones::build_stoppable(const std::vector<std::vector<int>>& successors,
                                    const std::vector<std::vector<int>>& predecessors) {
  // Stoppable for T: T's region touches no branch place's region of any type. Or every place it
  // touches lies on the robot's own lane, or on a way that only that lane leads into or out of (a
  // lane's split into the connectors of a junction, or the connectors merging into it): whoever
  // needs such a place drives along the waiting robot's lane and would queue behind or ahead of it
  // anyway, so nobody crossing the junction by another way is kept out. Without this, a one-way
  // link between two junctions closer than about two vehicle lengths has no stoppable place, and
  // both junctions with the link become one stretch that a robot holds all at once.
  const std::size_t places = position_.size();
  const std::size_t types = types_.size();
  constexpr int kChain = 64;  // longer than any junction connector, in places
  const auto only_via = [&](int place, int corridor, const std::vector<std::vector<int>>& links) {
    for (int at = place, step = 0; step < kChain; ++step) {
      if (corridor_[static_cast<std::size_t>(at)] == corridor) return true;
      const auto& next = links[static_cast<std::size_t>(at)];
      if (next.size() != 1) return false;
      at = next.front();
    }
    return false;
  };
  const auto own_lane = [&](int place, int corridor) {
    return only_via(place, corridor, predecessors) || only_via(place, corridor, successors);
  };
  stoppable_.assign(types, std::vector<std::uint8_t>(places, 1));
  stoppable_all_.assign(places, 1);
  for (std::size_t t = 0; t < types; ++t) {
    for (std::size_t p = 0; p < places; ++p) {
      bool touches_branch = false;
      bool own_lane_only = corridor_[p] >= 0 && !corridor_loop_[static_cast<std::size_t>(corridor_[p])];
      for (std::size_t u = 0; u < types; ++u) {
        for (int q : conflicts(static_cast<int>(t), static_cast<int>(p), static_cast<int>(u))) {
          touches_branch = touches_branch || branch_[static_cast<std::size_t>(q)];
          if (own_lane_only && !own_lane(q, corridor_[p])) own_lane_only = false;
        }
      }
      stoppable_[t][p] = !touches_branch || own_lane_only ? 1 : 0;
      if (!stoppable_[t][p]) stoppable_all_[p] = 0;
    }
  }
}

bool ConflictZones::conflict(int type_a, int place_a, int type_b, int place_b) const {
  const auto& c = conflicts(type_a, place_a, type_b);
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
