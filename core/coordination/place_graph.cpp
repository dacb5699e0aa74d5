#include "coordination/place_graph.hpp"

#include <algorithm>
#include <functional>
#include <queue>
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
  return distances_to(type, goal)[static_cast<std::size_t>(place)];
}

const std::vector<double>& PlaceGraph::distances_to(int type, int goal) {
  const std::int64_t key = static_cast<std::int64_t>(type) * place_count() + goal;
  if (const auto found = distances_.find(key); found != distances_.end()) return found->second;
  std::vector<double> metres(static_cast<std::size_t>(place_count()), kUnreachable);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  metres[static_cast<std::size_t>(goal)] = 0.0;
  open.push({0.0, goal});
  const auto& predecessors = predecessors_[static_cast<std::size_t>(type)];
  while (!open.empty()) {
    const auto [d, place] = open.top();
    open.pop();
    if (d > metres[static_cast<std::size_t>(place)]) continue;
    for (const int before : predecessors[static_cast<std::size_t>(place)]) {
      const double via = d + step_length(before, place);
      if (via < metres[static_cast<std::size_t>(before)]) {
        metres[static_cast<std::size_t>(before)] = via;
        open.push({via, before});
      }
    }
  }
  return distances_.emplace(key, std::move(metres)).first->second;
}

}  // namespace fleet::coordination
