#include "coordination/place_route.hpp"

#include <cmath>

namespace fleet::coordination {

void PlaceRoute::assign(const map::RoadGraph& graph, const traffic::ConflictZones& zones,
                        const std::vector<int>& route) {
  points = route;
  point_s.assign(route.size(), 0.0);
  places.clear();
  place_point.clear();
  for (std::size_t i = 0; i < route.size(); ++i) {
    if (i > 0) {
      const auto& a = graph.points[static_cast<std::size_t>(route[i - 1])];
      const auto& b = graph.points[static_cast<std::size_t>(route[i])];
      point_s[i] = point_s[i - 1] + std::hypot(b.x - a.x, b.y - a.y);
    }
    const int place = zones.place_of(route[i]);
    if (places.empty() || places.back() != place) {
      places.push_back(place);
      place_point.push_back(static_cast<int>(i));
    } else {
      place_point.back() = static_cast<int>(i);
    }
  }
}

int PlaceRoute::index_at(double progress) const {
  std::size_t i = 0;
  while (i + 1 < places.size() && progress >= 0.5 * (place_s(i) + place_s(i + 1))) ++i;
  return static_cast<int>(i);
}

std::vector<int> PlaceRoute::places_within(std::size_t from, double length) const {
  std::vector<int> within;
  for (std::size_t i = from; i < places.size() && (i == from || place_s(i) - place_s(from) <= length); ++i) {
    within.push_back(places[i]);
  }
  return within;
}

std::size_t PlaceRoute::leg_end(std::size_t from) const {
  // A route may turn back on itself (a robot turning round, or pushed back and coming on): where
  // it does, the place it turns at is the goal of the leg, not the route's end, which may be the
  // place the robot stands at.
  std::size_t end = from + 1;
  while (end + 1 < places.size() && places[end + 1] != places[end - 1]) ++end;
  return end;
}

}  // namespace fleet::coordination
