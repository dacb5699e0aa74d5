#include "coordination/place_traffic.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::coordination {

namespace {
// A robot standing still reports its body with a little noise: a change under this is none.
constexpr double kSameBodyM = 0.02;
}  // namespace

PlaceTraffic::PlaceTraffic(const map::RoadGraph& graph, const traffic::ConflictZones& zones,
                           const PlaceTrafficParams& params)
    : graph_(graph),
      zones_(zones),
      params_(params),
      places_(graph, zones),
      planner_(places_, params.seed),
      order_(zones),
      points_of_place_(zones.place_count()),
      closures_(zones) {
  for (std::size_t point = 0; point < zones.point_count(); ++point) {
    points_of_place_[static_cast<std::size_t>(zones.place_of(static_cast<int>(point)))].push_back(
        static_cast<int>(point));
  }
  for (const auto& type : zones.vehicle_types()) body_length_.push_back(traffic::footprint_length(type.footprint));
  if (params_.plan_period_s <= 0.0) {
    const double move = places_.mean_move_length();
    params_.plan_period_s = move > 0.0 && params_.speed > 0.0 ? move / params_.speed : 1.0;
  }
}

int PlaceTraffic::add_robot(int type) {
  const int number = order_.add_robot(type, 0);
  order_.stand(number, -1);
  Robot robot;
  robot.type = type;
  robots_.push_back(std::move(robot));
  return number;
}

bool PlaceTraffic::drive(int robot, std::uint64_t version, const std::vector<int>& points, double progress,
                         const geometry::Polygon& way_out) {
  if (points.empty() || !std::isfinite(progress)) return false;
  for (const int point : points) {
    if (point < 0 || static_cast<std::size_t>(point) >= zones_.point_count()) return false;
  }
  Robot& r = at(robot);
  r.progress = progress;
  const bool routed = r.mode == Mode::kDriving || r.mode == Mode::kWaitingToEnter;
  if (routed && version < r.version) return true;  // sent before its latest route reached it
  hold_way_out(robot, way_out);
  if (r.mode == Mode::kDriving && version == r.version) {
    // The route it was handed, as it drives it (joined from where it is): its places count.
    if (!r.adopted && points != r.points) {
      take_route(robot, version, points, progress);
      return true;
    }
    r.adopted = true;
    follow_progress(robot, progress);
    return true;
  }
  if (r.mode == Mode::kWaitingToEnter && version == r.version) return true;
  take_route(robot, version, points, progress);
  return true;
}

void PlaceTraffic::take_route(int robot, std::uint64_t version, const std::vector<int>& points, double progress) {
  Robot& r = at(robot);
  r.version = version;
  r.assign(graph_, zones_, points);
  r.adopted = true;
  const int here = r.index_at(progress);
  if (!order_.present(robot)) {
    if (r.mode != Mode::kWaitingToEnter) r.waiting_since = ++waits_begun_;
    r.mode = Mode::kWaitingToEnter;
    try_to_enter(robot);
    return;
  }
  r.mode = Mode::kDriving;
  // The route goes on from the place its current visit is of, near where it is along it.
  const int current = order_.current(robot);
  int start = -1;
  for (int i = std::min(here, static_cast<int>(r.places.size()) - 1); i >= 0 && start < 0; --i) {
    if (r.places[static_cast<std::size_t>(i)] == current) start = i;
  }
  if (start < 0) {
    // Somewhere its visits do not say (the robot went its own way): it stands where it is.
    place_robot(robot, r.places[static_cast<std::size_t>(here)]);
    r.at = here;
    follow_progress(robot, progress);
    return;
  }
  r.at = start;
  // Visits planned along another way than the new route's are dropped (one it has begun is kept:
  // its body is in that place already).
  for (int k = 1; k <= order_.pending(robot); ++k) {
    const std::size_t index = static_cast<std::size_t>(start + k);
    if (index >= r.places.size() || order_.visit_place(robot, k) != r.places[index]) {
      if (k == 1 && order_.has_left(robot)) {
        // Its body is past the middle of its move into a place the new route does not go on
        // through: it stands in that place, and a route from there on to the new route's end
        // keeps its visits and its route the same places.
        place_robot(robot, order_.visit_place(robot, 1));
        reroute(robot);
        return;
      }
      order_.drop_from(robot, k);
      break;
    }
  }
  follow_progress(robot, progress);
}

void PlaceTraffic::try_to_enter(int robot) {
  if (closed_stale_) rebuild_closed();
  Robot& r = at(robot);
  const int here = r.index_at(r.progress);
  const int place = r.places[static_cast<std::size_t>(here)];
  // Nobody's visit, begun or planned, may conflict with where it enters, no body or way out may
  // close that place, and nobody may be in the way out it sweeps to get there.
  std::vector<int> blockers = closers_of(robot, r.type, place, -1);
  if (!r.way_out.empty()) {
    const std::vector<int> in_area = robots_in_area(robot, r.way_out);
    blockers.insert(blockers.end(), in_area.begin(), in_area.end());
  }
  // Of two robots waiting to enter whose ways out meet, the one that began to wait first goes
  // first: the other's way out does not hold it up, only its body.
  std::erase_if(blockers, [&](int other) {
    const Robot& o = at(other);
    return o.mode == Mode::kWaitingToEnter && o.waiting_since > r.waiting_since &&
           !closures_.reaches(o.body, r.type, place) &&
           (r.way_out.empty() || o.body.empty() || !geometry::convex_polygons_overlap(o.body, r.way_out));
  });
  for (int other = 0; other < robots(); ++other) {
    if (other == robot) continue;
    const Robot& o = at(other);
    for (const int visit : order_.places_ahead(other)) {
      if (zones_.conflict(r.type, place, o.type, visit)) {
        blockers.push_back(other);
        break;
      }
    }
  }
  // Nor may anybody on the roads be about to drive where it makes its first move, a body length
  // on from where it enters: robots let on beside one another (neighbouring stalls that join one
  // lane) would each want the others' places at once, and pushing bodies that span several places
  // back into their stalls and out again in turn gets none of them onto the road. A robot that
  // waits for this one, or whose route leads through its body, does not hold it up.
  const std::vector<int> first_move =
      r.places_within(static_cast<std::size_t>(here), body_length_[static_cast<std::size_t>(r.type)]);
  const geometry::BoundingCircle body_circle = geometry::bounding_circle(r.body);
  for (int other = 0; other < robots(); ++other) {
    if (other == robot || !order_.present(other)) continue;
    const Robot& o = at(other);
    // Where it stands, then where it is about to drive.
    const std::vector<int> its_way = way_ahead(other);
    const auto conflicts_with = [&](const std::vector<int>& mine) {
      return std::any_of(its_way.begin() + 1, its_way.end(), [&](int visit) {
        return std::any_of(mine.begin(), mine.end(), [&](int p) { return zones_.conflict(r.type, p, o.type, visit); });
      });
    };
    bool waits_for_its_body =
        std::find(o.grant.waits_for.begin(), o.grant.waits_for.end(), robot) != o.grant.waits_for.end() ||
        (r.body.empty() && conflicts_with({place}));
    // Its route on, as far as it goes: a robot coming past where this one stands will wait for it.
    const bool routed = o.mode == Mode::kDriving && o.adopted && !o.places.empty();
    const std::vector<int> its_route =
        routed ? std::vector<int>(o.places.begin() + std::min<std::ptrdiff_t>(o.at, std::ssize(o.places) - 1),
                                  o.places.end())
               : its_way;
    for (std::size_t k = 1; k < its_route.size() && !r.body.empty() && !waits_for_its_body; ++k) {
      waits_for_its_body = zones_.may_reach(body_circle, o.type, its_route[k]) &&
                           zones_.body_reaches_move(r.body, o.type, its_route[k - 1], its_route[k]);
    }
    if (!waits_for_its_body && conflicts_with(first_move)) blockers.push_back(other);
  }
  std::sort(blockers.begin(), blockers.end());
  blockers.erase(std::unique(blockers.begin(), blockers.end()), blockers.end());
  r.entry_blockers = std::move(blockers);
  if (!r.entry_blockers.empty()) return;
  r.mode = Mode::kDriving;
  if (!r.body.empty() || r.reserves_entry) closed_stale_ = true;
  r.reserves_entry = false;
  r.body.clear();

  place_robot(robot, place);
  r.at = here;
  follow_progress(robot, r.progress);
}

std::vector<int> PlaceTraffic::way_ahead(int robot) const {
  std::vector<int> places{order_.current(robot)};
  for (int k = 1; k <= order_.pending(robot); ++k) places.push_back(order_.visit_place(robot, k));
  const Robot& r = at(robot);
  if (r.mode == Mode::kDriving && r.adopted && !r.places.empty()) {
    const auto last = std::min(static_cast<std::size_t>(r.at + order_.pending(robot)), r.places.size() - 1);
    const std::vector<int> on = r.places_within(last, body_length_[static_cast<std::size_t>(r.type)]);
    places.insert(places.end(), on.begin() + 1, on.end());
  }
  return places;
}

void PlaceTraffic::place_robot(int robot, int place) {
  order_.stand(robot, place);
  const int type = at(robot).type;
  drop_visits_into(robot, [&](int other_type, int q) { return zones_.conflict(other_type, q, type, place); });
}

template <typename Conflicts>
void PlaceTraffic::drop_visits_into(int robot, const Conflicts& conflicts) {
  for (int other = 0; other < robots(); ++other) {
    if (other == robot || !order_.present(other)) continue;
    for (int k = order_.has_left(other) ? 2 : 1; k <= order_.pending(other); ++k) {
      if (conflicts(at(other).type, order_.visit_place(other, k))) {
        order_.drop_from(other, k);
        break;
      }
    }
  }
}

std::vector<int> PlaceTraffic::robots_in_area(int robot, const geometry::Polygon& area) const {
  const BodyClosures::Circle around = BodyClosures::circle_around(area);
  std::vector<int> found;
  for (int other = 0; other < robots(); ++other) {
    if (other == robot) continue;
    const Robot& o = at(other);
    const geometry::Polygon& body = closing_body(o);
    bool inside = (!body.empty() && geometry::convex_polygons_overlap(body, area)) ||
                  (!o.way_out.empty() && geometry::convex_polygons_overlap(o.way_out, area));
    for (const int place : order_.places_ahead(other))
      inside = inside || closures_.reaches(area, around, o.type, place);
    if (inside) found.push_back(other);
  }
  return found;
}

void PlaceTraffic::stand(int robot, const geometry::Polygon& body, const geometry::Polygon& to_sweep) {
  Robot& r = at(robot);
  if (order_.present(robot)) order_.stand(robot, -1);
  r.points.clear();
  r.places.clear();
  r.place_point.clear();
  r.entry_blockers.clear();
  r.stopped_for.clear();
  r.kept_by.clear();
  r.adopted = true;
  r.mode = body.empty() ? Mode::kOff : Mode::kStanding;
  if (!geometry::same_polygon(to_sweep, r.way_out, kSameBodyM)) {
    r.way_out = to_sweep;
    closed_stale_ = true;
  }
  take_body(robot, body);
}

void PlaceTraffic::stopped_for(int robot, std::vector<int> others) {
  std::erase_if(others, [&](int other) { return other == robot || other < 0 || other >= robots(); });
  at(robot).stopped_for = std::move(others);
}

void PlaceTraffic::waiting_body(int robot, const geometry::Polygon& body) {
  if (at(robot).mode == Mode::kWaitingToEnter) take_body(robot, body);
}

void PlaceTraffic::take_body(int robot, const geometry::Polygon& body) {
  Robot& r = at(robot);
  if (geometry::same_polygon(body, r.body, kSameBodyM)) return;
  r.body = body;
  closed_stale_ = true;
  if (body.empty()) return;
  // Plans made before it stood here may lead into its body: those visits go, not yet begun.
  const BodyClosures::Circle around = BodyClosures::circle_around(body);
  drop_visits_into(robot, [&](int type, int place) { return closures_.reaches(body, around, type, place); });
}

void PlaceTraffic::hold_way_out(int robot, const geometry::Polygon& way_out) {
  // Robots already in the way out may drive on out of it; others' plans keep out of it
  // (ClosedPlaces::by_area). Visits planned into it before stay: the robot enters once they end.
  Robot& r = at(robot);
  if (geometry::same_polygon(way_out, r.way_out, kSameBodyM)) return;
  r.way_out = way_out;
  closed_stale_ = true;
}

const geometry::Polygon& PlaceTraffic::closing_body(const Robot& r) {
  static const geometry::Polygon kNone;
  return r.mode == Mode::kStanding || r.mode == Mode::kWaitingToEnter ? r.body : kNone;
}

std::vector<int> PlaceTraffic::closers_of(int robot, int type, int place, int from) const {
  std::vector<int> closers;
  if (closures_.closer(type, place, robot, from) == kOpen) return closers;
  for (int other = 0; other < robots(); ++other) {
    if (other == robot) continue;
    const Robot& o = at(other);
    const bool inside = from >= 0 && closures_.reaches(o.way_out, type, from);
    if (closures_.reaches(closing_body(o), type, place) || (!inside && closures_.reaches(o.way_out, type, place))) {
      closers.push_back(other);
    }
  }
  return closers;
}

void PlaceTraffic::rebuild_closed() {
  std::vector<BesideTheRoads> beside(robots_.size());
  for (int robot = 0; robot < robots(); ++robot) {
    const Robot& r = at(robot);
    BesideTheRoads& b = beside[static_cast<std::size_t>(robot)];
    b.type = r.type;
    b.body = &closing_body(r);
    b.way_out = &r.way_out;
    if (r.reserves_entry && r.mode == Mode::kWaitingToEnter && !r.places.empty()) {
      b.held_entry = r.places[static_cast<std::size_t>(r.index_at(r.progress))];
    }
  }
  closures_.rebuild(beside);
  closed_stale_ = false;
}

void PlaceTraffic::follow_progress(int robot, double progress) {
  // The robot reports where it is; its visits end as it drives through them. A robot stops at
  // the end of its grant a little short of the point: that close counts as arrived (well past the
  // move's midpoint however short the move).
  constexpr double kArrivedM = 0.05;
  Robot& r = at(robot);
  if (r.mode != Mode::kDriving || !r.adopted) return;
  while (static_cast<std::size_t>(r.at) + 1 < r.places.size()) {
    const auto i = static_cast<std::size_t>(r.at);
    if (order_.next(robot) != r.places[i + 1]) break;
    const double from = r.place_s(i);
    const double to = r.place_s(i + 1);
    if (!order_.has_left(robot)) {
      if (progress < 0.5 * (from + to) || order_.waits_for(robot) >= 0) break;
      order_.leave(robot);
    }
    if (progress < to - std::min(kArrivedM, 0.25 * (to - from))) break;
    order_.arrive(robot);
    ++r.at;
  }
}

}  // namespace fleet::coordination
