#include "coordination/place_graph.hpp"

#include <algorithm>
#include <utility>

#include "traffic/vehicle_lanes.hpp"

namespace fleet::coordination {

PlaceGraph::PlaceGraph(const map::RoadGraph& graph, const traffic::ConflictZones& zones) : zones_(zones) {
  const std::size_t places = zones.place_count();
  for (const traffic::VehicleType& type : zones.vehicle_types()) {
    const map::RoadGraph lanes =
        traffic::lane_graph_for(graph, traffic::footprint_width(type.footprint), zones.params().margin);
    std::vector<std::vector<int>> successors(places);
    std::vector<std::vector<int>> predecessors(places);
    for (std::size_t point = 0; point < lanes.successors.size(); ++point) {
      const int from = zones.place_of(static_cast<int>(point));
      for (const int next : lanes.successors[point]) {
        const int to = zones.place_of(next);
        if (to == from) continue;
        auto& out = successors[static_cast<std::size_t>(from)];
        if (std::find(out.begin(), out.end(), to) != out.end()) continue;
        out.push_back(to);
        predecessors[static_cast<std::size_t>(to)].push_back(from);
      }
    }
    successors_.push_back(std::move(successors));
    predecessors_.push_back(std::move(predecessors));
  }
}

double PlaceGraph::step_length(int from, int to) const {
  return geometry::distance(zones_.position(from), zones_.position(to));
}

double PlaceGraph::mean_move_length() const {
  double metres = 0.0;
  int moves = 0;
  for (int place = 0; place < place_count(); ++place) {
    for (const int next : successors(0, place)) {
      metres += step_length(place, next);
      ++moves;
    }
  }
  return moves > 0 ? metres / moves : 0.0;
}

double PlaceGraph::distance(int type, int place, int goal) {
  GoalSearch& search = search_for(type, place, goal);
  search.last_asked = ++asked_;
  if (!search.settled[static_cast<std::size_t>(place)]) settle(search, type, place);
  return search.metres[static_cast<std::size_t>(place)];
}

PlaceGraph::GoalSearch& PlaceGraph::search_for(int type, int place, int goal) {
  const std::int64_t key = static_cast<std::int64_t>(type) * place_count() + goal;
  if (const auto found = searches_.find(key); found != searches_.end()) return found->second;
  if (searches_.size() >= kMaxGoalSearches) {
    const auto oldest = std::min_element(searches_.begin(), searches_.end(), [](const auto& a, const auto& b) {
      return a.second.last_asked < b.second.last_asked;
    });
    searches_.erase(oldest);
  }
  GoalSearch& search = searches_[key];
  search.towards = zones_.position(place);
  search.metres.assign(static_cast<std::size_t>(place_count()), kUnreachable);
  search.settled.assign(static_cast<std::size_t>(place_count()), false);
  search.metres[static_cast<std::size_t>(goal)] = 0.0;
  search.open.push({geometry::distance(zones_.position(goal), search.towards), goal});
  return search;
}

void PlaceGraph::settle(GoalSearch& search, int type, int place) {
  const auto& predecessors = predecessors_[static_cast<std::size_t>(type)];
  while (!search.open.empty()) {
    const int next = search.open.top().second;
    search.open.pop();
    if (search.settled[static_cast<std::size_t>(next)]) continue;
    search.settled[static_cast<std::size_t>(next)] = true;
    ++places_settled_;
    const double metres = search.metres[static_cast<std::size_t>(next)];
    for (const int before : predecessors[static_cast<std::size_t>(next)]) {
      const double via = metres + step_length(before, next);
      if (via < search.metres[static_cast<std::size_t>(before)]) {
        search.metres[static_cast<std::size_t>(before)] = via;
        search.open.push({via + geometry::distance(zones_.position(before), search.towards), before});
      }
    }
    if (next == place) return;
  }
}

}  // namespace fleet::coordination
