#include "coordination/visit_order.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace fleet::coordination {

void VisitOrder::open(int robot, const Visit& visit) {
  open_[static_cast<std::size_t>(visit.place)].push_back({robot, visit.step});
}

void VisitOrder::close(int robot, const Visit& visit) {
  auto& list = open_[static_cast<std::size_t>(visit.place)];
  const auto it =
      std::find_if(list.begin(), list.end(), [&](const Open& o) { return o.robot == robot && o.step == visit.step; });
  if (it != list.end()) list.erase(it);
}

int VisitOrder::add_robot(int type, int place) {
  Robot robot;
  robot.type = type;
  robot.visits.push_back({place, 0});
  robots_.push_back(std::move(robot));
  const int number = static_cast<int>(robots_.size()) - 1;
  open(number, robots_.back().visits.front());
  return number;
}

void VisitOrder::stand(int robot, int place) {
  Robot& r = robots_[static_cast<std::size_t>(robot)];
  for (std::size_t k = r.left ? 1 : 0; k < r.visits.size(); ++k) close(robot, r.visits[k]);
  r.visits.clear();
  r.left = false;
  if (place >= 0) {
    r.visits.push_back({place, 0});
    open(robot, r.visits.front());
  }
}

void VisitOrder::drop_from(int robot, int k) {
  Robot& r = robots_[static_cast<std::size_t>(robot)];
  const std::size_t keep = std::max<std::size_t>(static_cast<std::size_t>(std::max(k, 0)), r.left ? 2 : 1);
  if (r.visits.size() <= keep) return;
  for (std::size_t j = keep; j < r.visits.size(); ++j) close(robot, r.visits[j]);
  r.visits.resize(keep);
}

void VisitOrder::plan(int robot, int place, std::size_t step) {
  Robot& r = robots_[static_cast<std::size_t>(robot)];
  if (r.visits.empty()) {
    throw std::invalid_argument("visit order: robot " + std::to_string(robot) + " is planned but off the roads");
  }
  if (step <= r.visits.back().step) {
    throw std::invalid_argument("visit order: robot " + std::to_string(robot) + " planned at step " +
                                std::to_string(step) + ", not after its last visit's");
  }
  r.visits.push_back({place, step});
  open(robot, r.visits.back());
}

int VisitOrder::place(int robot) const {
  const Robot& r = at(robot);
  if (r.visits.empty()) return -1;
  return r.left ? r.visits[1].place : r.visits[0].place;
}

int VisitOrder::next(int robot) const {
  const Robot& r = at(robot);
  return r.visits.size() > 1 ? r.visits[1].place : -1;
}

std::vector<int> VisitOrder::places_ahead(int robot) const {
  std::vector<int> places;
  const Robot& r = at(robot);
  for (std::size_t k = r.left ? 1 : 0; k < r.visits.size(); ++k) places.push_back(r.visits[k].place);
  return places;
}

int VisitOrder::waits_for(int robot, int visit) const {
  const Robot& r = at(robot);
  if (visit < 1 || static_cast<std::size_t>(visit) >= r.visits.size()) return -1;
  const Visit& next = r.visits[static_cast<std::size_t>(visit)];
  // Other robots' visits not ended (the one a robot is leaving has ended once it has left) of
  // places conflicting with this one, which the plan has begin before it; the lowest-numbered
  // such robot.
  int found = -1;
  for (int other_type = 0; other_type < static_cast<int>(zones_.type_count()); ++other_type) {
    for (const int place : zones_.conflicts(r.type, next.place, other_type)) {
      for (const Open& o : open_[static_cast<std::size_t>(place)]) {
        if (o.robot == robot || o.step >= next.step || at(o.robot).type != other_type) continue;
        if (found < 0 || o.robot < found) found = o.robot;
      }
    }
  }
  return found;
}

void VisitOrder::leave(int robot) {
  Robot& r = robots_[static_cast<std::size_t>(robot)];
  if (r.left) return;
  if (r.visits.size() < 2) throw std::logic_error("visit order: robot " + std::to_string(robot) + " has nowhere to go");
  if (const int other = waits_for(robot); other >= 0) {
    throw std::logic_error("visit order: robot " + std::to_string(robot) + " would pass robot " +
                           std::to_string(other) + "'s earlier visit");
  }
  r.left = true;
  close(robot, r.visits.front());
}

void VisitOrder::arrive(int robot) {
  leave(robot);
  Robot& r = robots_[static_cast<std::size_t>(robot)];
  r.visits.pop_front();
  r.left = false;
}

std::vector<int> VisitOrder::wait_cycle() const {
  const std::size_t n = robots_.size();
  std::vector<int> waiting_for(n, -1);
  for (std::size_t i = 0; i < n; ++i) {
    if (!robots_[i].left) waiting_for[i] = waits_for(static_cast<int>(i));
  }
  for (std::size_t i = 0; i < n; ++i) {
    // Walking the waits from any robot of a cycle comes back to it within n steps.
    int at_robot = static_cast<int>(i);
    for (std::size_t hops = 0; hops < n && at_robot >= 0; ++hops) {
      at_robot = waiting_for[static_cast<std::size_t>(at_robot)];
      if (at_robot == static_cast<int>(i)) {
        std::vector<int> cycle{static_cast<int>(i)};
        for (int k = waiting_for[i]; k != static_cast<int>(i); k = waiting_for[static_cast<std::size_t>(k)]) {
          cycle.push_back(k);
        }
        return cycle;
      }
    }
  }
  return {};
}

}  // namespace fleet::coordination
