#include "coordination/body_closures.hpp"

#include <algorithm>

namespace fleet::coordination {

BodyClosures::BodyClosures(const traffic::ConflictZones& zones)
    : zones_(zones), index_(zones), closed_(zones.type_count(), zones.place_count()) {}

BodyClosures::Circle BodyClosures::circle_around(const geometry::Polygon& body) {
  Circle circle{geometry::vertex_centroid(body), 0.0};
  for (const auto& v : body) circle.radius = std::max(circle.radius, geometry::distance(circle.centre, v));
  return circle;
}

bool BodyClosures::reaches(const geometry::Polygon& body, int type, int place) const {
  return !body.empty() && reaches(body, circle_around(body), type, place);
}

bool BodyClosures::reaches(const geometry::Polygon& body, const Circle& around, int type, int place) const {
  if (body.empty()) return false;
  if (geometry::distance(around.centre, zones_.position(place)) > around.radius + zones_.reach(type, place)) {
    return false;
  }
  for (const auto& polygon : zones_.region(type, place)) {
    if (geometry::convex_polygons_overlap(body, polygon)) return true;
  }
  return false;
}

namespace {

/// `robot` closes what `closer` says of a place: it alone, or it and others.
void mark(int& closer, int robot) {
  closer = closer == kOpen || closer == robot ? robot : kClosedByMany;
}

}  // namespace

void BodyClosures::close(std::vector<std::vector<int>>& layer, int robot, const geometry::Polygon& polygon) {
  if (polygon.empty()) return;
  const Circle around = circle_around(polygon);
  for (const int place : places_near(around)) {
    for (int type = 0; type < static_cast<int>(zones_.type_count()); ++type) {
      if (reaches(polygon, around, type, place))
        mark(layer[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)], robot);
    }
  }
}

void BodyClosures::close_to_moves(int robot, const geometry::Polygon& body) {
  // A body may close a place only to some of the moves into it (a parked truck's body beside a
  // junction reaches what a truck turning there sweeps, not what one driving straight through
  // does): for every move into a place it reaches, from a neighbour, whether it reaches what that
  // move sweeps. A move's polygons are some of the place's, so only bodies that reach the place
  // can close a move into it.
  if (body.empty()) return;
  const Circle around = circle_around(body);
  for (const int place : places_near(around)) {
    for (int type = 0; type < static_cast<int>(zones_.type_count()); ++type) {
      if (!reaches(body, around, type, place)) continue;
      mark(closed_.by_body[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)], robot);
      auto& by_move = closed_.by_move[static_cast<std::size_t>(type)];
      for (const int from : zones_.neighbours(place)) {
        int& closer = by_move.try_emplace(ClosedPlaces::move_key(from, place), kOpen).first->second;
        if (zones_.body_reaches_move(body, type, from, place)) mark(closer, robot);
      }
    }
  }
}

void BodyClosures::rebuild(const std::vector<BesideTheRoads>& robots) {
  for (auto* layer : {&closed_.by_body, &closed_.by_area}) {
    for (auto& by_place : *layer) std::fill(by_place.begin(), by_place.end(), kOpen);
  }
  for (auto& by_move : closed_.by_move) by_move.clear();
  for (int robot = 0; robot < static_cast<int>(robots.size()); ++robot) {
    const BesideTheRoads& r = robots[static_cast<std::size_t>(robot)];
    if (r.body != nullptr) close_to_moves(robot, *r.body);
    if (r.way_out != nullptr) close(closed_.by_area, robot, *r.way_out);
    if (r.held_entry < 0) continue;
    // Where it enters is held as a way out is: closed to robots outside, and those in places
    // conflicting with it are pushed out.
    for (int type = 0; type < static_cast<int>(zones_.type_count()); ++type) {
      for (const int place : zones_.conflicts(type, r.held_entry, r.type)) {
        mark(closed_.by_area[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)], robot);
      }
    }
  }
}

}  // namespace fleet::coordination
