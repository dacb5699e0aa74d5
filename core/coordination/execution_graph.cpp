#include "coordination/execution_graph.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fleet::coordination {

ExecutionGraph::ExecutionGraph(int places, int robots)
    : routes_(static_cast<std::size_t>(robots)),
      position_(static_cast<std::size_t>(robots), 0),
      place_queue_(static_cast<std::size_t>(places)) {}

void ExecutionGraph::load(const std::vector<PlannedRoute>& routes) {
  if (routes.size() != routes_.size()) {
    throw std::invalid_argument("execution graph: a plan of " + std::to_string(routes.size()) + " routes for " +
                                std::to_string(routes_.size()) + " robots");
  }
  struct Entry {
    int place, step, robot, index;
  };
  std::vector<Entry> entries;
  const int places = static_cast<int>(place_queue_.size());
  for (int r = 0; r < robots(); ++r) {
    const PlannedRoute& route = routes[r];
    if (route.places.empty() || route.places.size() != route.entry_steps.size()) {
      throw std::invalid_argument("execution graph: robot " + std::to_string(r) + " has an empty or ragged route");
    }
    for (std::size_t k = 0; k < route.places.size(); ++k) {
      if (route.places[k] < 0 || route.places[k] >= places) {
        throw std::invalid_argument("execution graph: robot " + std::to_string(r) + " plans place " +
                                    std::to_string(route.places[k]) + ", out of range");
      }
      if (k > 0 && route.entry_steps[k] <= route.entry_steps[k - 1]) {
        throw std::invalid_argument("execution graph: robot " + std::to_string(r) + "'s entry steps do not rise");
      }
      entries.push_back({route.places[k], route.entry_steps[k], r, static_cast<int>(k)});
    }
  }
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.place != b.place ? a.place < b.place : a.step < b.step; });
  for (auto& queue : place_queue_) queue.clear();
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i > 0 && entries[i].place == entries[i - 1].place && entries[i].step == entries[i - 1].step) {
      throw std::invalid_argument("execution graph: robots " + std::to_string(entries[i - 1].robot) + " and " +
                                  std::to_string(entries[i].robot) + " both planned to enter place " +
                                  std::to_string(entries[i].place) + " at step " + std::to_string(entries[i].step));
    }
    place_queue_[entries[i].place].push_back({entries[i].robot, entries[i].index});
  }
  routes_ = routes;
  std::fill(position_.begin(), position_.end(), 0);
}

int ExecutionGraph::current_place(int robot) const {
  return routes_[robot].places[position_[robot]];
}

int ExecutionGraph::next_place(int robot) const {
  const auto& places = routes_[robot].places;
  const std::size_t next = static_cast<std::size_t>(position_[robot]) + 1;
  return next < places.size() ? places[next] : -1;
}

int ExecutionGraph::waits_for(int robot) const {
  const int next = next_place(robot);
  if (next < 0) return -1;
  const Visit& first = place_queue_[next].front();
  return first.robot == robot && first.index == position_[robot] + 1 ? -1 : first.robot;
}

void ExecutionGraph::advance(int robot) {
  if (next_place(robot) < 0) {
    throw std::logic_error("execution graph: robot " + std::to_string(robot) + " advanced past its route");
  }
  if (const int other = waits_for(robot); other >= 0) {
    throw std::logic_error("execution graph: robot " + std::to_string(robot) + " entered place " +
                           std::to_string(next_place(robot)) + " before robot " + std::to_string(other) +
                           "'s visit ordered before it ended");
  }
  place_queue_[current_place(robot)].pop_front();
  ++position_[robot];
}

int ExecutionGraph::pending_visits() const {
  int n = 0;
  for (int r = 0; r < robots(); ++r) n += static_cast<int>(routes_[r].places.size()) - 1 - position_[r];
  return n;
}

std::vector<int> ExecutionGraph::wait_cycle() const {
  // Each robot waits for at most one other, so the wait-for graph is a functional graph: walk each
  // chain once, colouring robots by the walk that first reached them.
  std::vector<int> walk_of(routes_.size(), -1);
  for (int start = 0; start < robots(); ++start) {
    int r = start;
    while (r >= 0 && walk_of[r] < 0) {
      walk_of[r] = start;
      r = waits_for(r);
    }
    if (r >= 0 && walk_of[r] == start) {
      std::vector<int> cycle{r};
      for (int m = waits_for(r); m != r; m = waits_for(m)) cycle.push_back(m);
      return cycle;
    }
  }
  return {};
}

}  // namespace fleet::coordination
