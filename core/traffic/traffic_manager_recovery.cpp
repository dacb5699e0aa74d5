// The TrafficManager's ways out of waiting: re-routes, sidings and breaking wait-for cycles.

#include <algorithm>
#include <cmath>
#include <functional>

#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_manager_detail.hpp"

namespace fleet::traffic {

using detail::direction_in;
using detail::kActOnInstruction;
using detail::kInfinity;
using detail::sort_unique;

// ---- re-routes and sidings -------------------------------------------------------------------------

std::vector<std::uint8_t> TrafficManager::places_of_others(const std::vector<int>& others, bool with_next_stretch,
                                                           double window, int type) const {
  std::vector<std::uint8_t> mask(zones_->place_count(), 0);
  int holder_type = 0;
  auto add = [&](int p) {
    for (int q : zones_->conflicts(holder_type, p, type)) mask[static_cast<std::size_t>(q)] = 1;
  };
  for (int id : others) {
    auto it = robots_.find(id);
    if (it == robots_.end()) continue;
    const Robot& o = it->second;
    holder_type = o.type;
    // A body it stands with (beside the roads, or not yet off the place it backed out of) and the
    // area of its turn into a place close the places they touch, as place_free_for counts them.
    const auto close_reach = [&](const std::vector<std::vector<int>>& reach) {
      if (reach.empty()) return;
      for (int q : reach[static_cast<std::size_t>(type)]) mask[static_cast<std::size_t>(q)] = 1;
    };
    close_reach(o.body_reach);
    if (o.arrival_held) close_reach(o.arrival_reach);
    for (int p : o.trail) add(p);
    int end = o.grant_end;
    if (with_next_stretch) end = std::max(end, next_stretch_end(o));
    for (int k = o.first_held; k <= end; ++k) add(o.places[static_cast<std::size_t>(k)]);
    for (int k = o.first_held;
         k < static_cast<int>(o.route.size()) && o.cum[static_cast<std::size_t>(k)] <= o.progress + window; ++k) {
      add(o.places[static_cast<std::size_t>(k)]);
    }
  }
  return mask;
}

geometry::Vec2 TrafficManager::position_of(const Robot& robot) const {
  // Standing beside the roads: where its body is.
  if (robot.frozen && !robot.body_polygon.empty()) {
    geometry::Vec2 sum{0.0, 0.0};
    for (const geometry::Vec2& v : robot.body_polygon) sum = {sum.x + v.x, sum.y + v.y};
    const auto n = static_cast<double>(robot.body_polygon.size());
    return {sum.x / n, sum.y / n};
  }
  const auto point = [&](std::size_t k) {
    const map::GraphPoint& p = graph_.points[static_cast<std::size_t>(robot.route[k])];
    return geometry::Vec2{p.x, p.y};
  };
  std::size_t k = 0;
  while (k + 1 < robot.route.size() && robot.cum[k + 1] <= robot.progress) ++k;
  if (k + 1 >= robot.route.size()) return point(k);
  const double length = robot.cum[k + 1] - robot.cum[k];
  const double f = length > 0.0 ? std::clamp((robot.progress - robot.cum[k]) / length, 0.0, 1.0) : 0.0;
  const geometry::Vec2 a = point(k), b = point(k + 1);
  return {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y)};
}

std::vector<std::uint8_t> TrafficManager::towards_stoppers(const Robot& robot) const {
  std::vector<std::uint8_t> mask(zones_->place_count(), 0);
  std::vector<geometry::Vec2> stoppers;
  for (int id : robot.stopped_for) {
    if (const auto it = robots_.find(id); id != robot.id && it != robots_.end())
      stoppers.push_back(position_of(it->second));
  }
  if (stoppers.empty()) return mask;
  // The safety check lets a robot move apart from a body it stopped for, never closer: a way that
  // first leads nearer a stopper than the robot stands now is one it cannot drive. A little
  // slack keeps the points beside it (as far from the stopper as it is) open.
  constexpr double kSlack = 0.05;  // metres
  const geometry::Vec2 here = position_of(robot);
  for (std::size_t p = 0; p < graph_.points.size(); ++p) {
    const geometry::Vec2 q{graph_.points[p].x, graph_.points[p].y};
    for (const geometry::Vec2& s : stoppers) {
      if (geometry::distance(q, s) < geometry::distance(here, s) - kSlack) {
        mask[static_cast<std::size_t>(zones_->place_of(static_cast<int>(p)))] = 1;
        break;
      }
    }
  }
  return mask;
}

std::vector<std::uint8_t> TrafficManager::closed_to(const Robot& robot, const std::vector<int>& others,
                                                    bool with_next_stretch) const {
  auto closed = places_of_others(others, with_next_stretch, 0.0, robot.type);
  const auto towards = towards_stoppers(robot);
  for (std::size_t p = 0; p < closed.size(); ++p) closed[p] = static_cast<std::uint8_t>(closed[p] | towards[p]);
  // Every corridor closed behind a transporter, but its own pair's: a way round leads elsewhere,
  // not into the lane another pair closes (it would wait there, on the way of that pair's picker).
  for (const PairClosure& closure : pair_closures_) {
    if (robot.id == closure.loader_id || partnered(robot.id, closure.loader_id)) continue;
    for (std::size_t p = 0; p < closed.size(); ++p) {
      const int at = zones_->corridor_index(static_cast<int>(p));
      if (zones_->corridor(static_cast<int>(p)) == closure.corridor && at >= closure.lo && at <= closure.hi)
        closed[p] = 1;
    }
  }
  return closed;
}

bool TrafficManager::first_stretch_free(const std::vector<int>& points, int slot) const {
  std::vector<int> places(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) places[i] = zones_->place_of(points[i]);
  const int last = static_cast<int>(places.size()) - 1;
  const int type = slots_[static_cast<std::size_t>(slot)]->type;
  std::vector<int> blockers;
  for (int j = 1; j <= last; ++j) {
    if (!place_free_for(slot, places, j, blockers)) return false;
    if (zones_->stoppable(type, places[static_cast<std::size_t>(j)])) break;
  }
  return true;
}

int TrafficManager::slot_of(int robot_id) const {
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    if (slots_[s]->id == robot_id) return static_cast<int>(s);
  }
  return -1;
}

void TrafficManager::replace_route(Robot& robot, std::vector<int> points, Instruction instruction, double now) {
  change_route(robot, std::move(points), robot.version + 1, /*sent=*/true);
  leave_arrival(robot);
  robot.pending = instruction;
  robot.last_reroute = now;
}

bool TrafficManager::reroute(Robot& robot, const std::vector<int>& others, double now, UpdateResult& out,
                             TrafficEvent::Kind kind, bool against_one_way) {
  const int slot = slot_of(robot.id);
  const int from = anchor_index(robot);
  const int anchor = robot.route[static_cast<std::size_t>(from)];
  const int goal = robot.route.back();
  const auto blocked = closed_to(robot, others, true);
  const TypeGraphs& graphs = *types_[static_cast<std::size_t>(robot.type)];
  std::vector<int> path = (against_one_way ? graphs.search : graphs.route_search)->shortest(anchor, goal, &blocked);
  if (path.size() < 2) return false;
  // Only a different way helps, and only one the robot can start on now.
  std::vector<int> remaining(robot.route.begin() + from, robot.route.end());
  if (path == remaining) return false;
  if (!first_stretch_free(path, slot)) return false;
  replace_route(robot, std::move(path), Instruction::kReroute, now);
  out.events.push_back({kind, now, robot.id, others});
  return true;
}

bool TrafficManager::send_to_siding(Robot& robot, const std::vector<int>& others, double now, UpdateResult& out,
                                    bool clear_of_self) {
  const int slot = slot_of(robot.id);
  const int anchor = robot.route[static_cast<std::size_t>(anchor_index(robot))];
  std::vector<std::uint8_t> here(zones_->place_count(), 0);
  if (clear_of_self) {
    for (int p : held_places(robot.id)) {
      for (int q : zones_->conflicts(robot.type, p, robot.type)) here[static_cast<std::size_t>(q)] = 1;
    }
  }
  // The robot may drive through nothing another robot holds ...
  std::vector<int> everyone;
  for (const auto& [id, o] : robots_) {
    if (id != robot.id) everyone.push_back(id);
  }
  const auto through = closed_to(robot, everyone, false);
  // ... and must end off the others' remaining routes, or it would stand in their way again; when
  // no such place is reachable, off their next `siding_window` metres (they pass it before it
  // matters). Never in a docked robot's way out (keep_clear).
  std::vector<int> path;
  for (double window : {kInfinity, configuration_.siding_window}) {
    auto avoid = places_of_others(others, true, window, robot.type);
    for (std::size_t p = 0; p < avoid.size(); ++p) {
      avoid[p] = static_cast<std::uint8_t>(avoid[p] | through[p] | here[p]);
    }
    path = types_[static_cast<std::size_t>(robot.type)]->search->nearest(
        anchor,
        [&](int place) {
          return zones_->stoppable(robot.type, place) && !stop_kept_clear(robot, place) &&
                 avoid[static_cast<std::size_t>(place)] == 0;
        },
        &through);
    if (path.size() >= 2) break;
  }
  if (path.size() < 2) return false;
  if (!first_stretch_free(path, slot)) return false;
  const int goal = robot.in_siding ? robot.resume_goal : robot.route.back();
  replace_route(robot, std::move(path), Instruction::kSiding, now);
  robot.in_siding = true;
  robot.resume_goal = goal;
  robot.yield_to = others;
  robot.siding_arrival = -1.0;
  out.events.push_back({TrafficEvent::Kind::kSidingSent, now, robot.id, others});
  return true;
}

void TrafficManager::try_resume(Robot& robot, double now, UpdateResult& out) {
  const int last = static_cast<int>(robot.route.size()) - 1;
  if (!robot.in_siding || robot.grant_end != last || !robot.stopped) return;
  if (robot.siding_arrival < 0.0) robot.siding_arrival = now;
  const TypeGraphs& graphs = *types_[static_cast<std::size_t>(robot.type)];
  std::vector<int> path = graphs.route_search->shortest(robot.route.back(), robot.resume_goal, nullptr);
  if (path.empty()) path = graphs.search->shortest(robot.route.back(), robot.resume_goal, nullptr);
  if (path.size() < 2) {
    // At the goal already, or the goal is unreachable: nothing to resume.
    if (path.size() == 1) robot.in_siding = false;
    return;
  }
  std::vector<int> alive;
  for (int id : robot.yield_to) {
    if (robots_.count(id) != 0) alive.push_back(id);
  }
  const auto theirs = places_of_others(alive, true, configuration_.siding_window, robot.type);
  bool clear = true;
  double travelled = 0.0;
  for (std::size_t i = 1; i < path.size() && travelled <= configuration_.siding_window; ++i) {
    travelled += search_->edge_length(path[i - 1], path[i]);
    if (theirs[static_cast<std::size_t>(zones_->place_of(path[i]))]) {
      clear = false;
      break;
    }
  }
  if (!clear && now - robot.siding_arrival < configuration_.yield_timeout) return;
  replace_route(robot, std::move(path), Instruction::kReroute, now);
  robot.in_siding = false;
  out.events.push_back({TrafficEvent::Kind::kResumed, now, robot.id, robot.yield_to});
  robot.yield_to.clear();
}

bool TrafficManager::needs_places_up_to(const Robot& waiter, const Robot& holder, int reached) const {
  std::vector<int> kept(holder.trail);
  for (int k = holder.first_held; k <= reached; ++k) kept.push_back(holder.places[static_cast<std::size_t>(k)]);
  const int last = static_cast<int>(waiter.route.size()) - 1;
  for (int j = waiter.grant_end + 1; j <= last; ++j) {
    const int q = waiter.places[static_cast<std::size_t>(j)];
    for (int p : kept) {
      const auto& in_conflict = zones_->conflicts(holder.type, p, waiter.type);
      if (std::find(in_conflict.begin(), in_conflict.end(), q) != in_conflict.end()) return true;
    }
    if (zones_->stoppable(waiter.type, q)) break;
  }
  return false;
}

bool TrafficManager::give_way(Robot& robot, const std::vector<int>& members, double now, UpdateResult& out) {
  if (robot.frozen || !robot.giving_way_to.empty()) return false;
  std::vector<int> stoppers;
  for (int id : robot.stopped_for) {
    if (id != robot.id && std::find(members.begin(), members.end(), id) != members.end()) stoppers.push_back(id);
  }
  if (stoppers.empty()) return false;
  const int reached = reached_index(robot);
  if (reached >= robot.grant_end) return false;
  // Giving back the road beyond itself helps only a stopper free to drive into it: not one whose
  // own safety check stops it for this robot's body, nor one whose next stretch is in conflict
  // with where this robot stands. Those wait for its body, which must move.
  const bool frees_a_stopper = std::any_of(stoppers.begin(), stoppers.end(), [&](int id) {
    const Robot& stopper = robots_.at(id);
    return !std::binary_search(stopper.stopped_for.begin(), stopper.stopped_for.end(), robot.id) &&
           !needs_places_up_to(stopper, robot, reached);
  });
  if (!frees_a_stopper) return false;
  robot.grant_end = reached;
  robot.giving_way_to = std::move(stoppers);
  out.events.push_back({TrafficEvent::Kind::kGaveWay, now, robot.id, robot.giving_way_to});
  return true;
}

// Tarjan's strongly connected components over the wait-for graph of stopped, waiting robots.
void TrafficManager::resolve_cycles(double now, UpdateResult& out) {
  const std::size_t n = slots_.size();
  std::vector<std::vector<int>> edges(n);
  for (std::size_t s = 0; s < n; ++s) {
    const Robot& r = *slots_[s];
    if (r.wait_since < 0.0) continue;
    for (int id : r.blocked_by) {
      const int t = slot_of(id);
      if (t >= 0 && slots_[static_cast<std::size_t>(t)]->wait_since >= 0.0) edges[s].push_back(t);
    }
  }
  std::vector<int> index(n, -1), low(n, 0), stack;
  std::vector<std::uint8_t> on_stack(n, 0);
  std::vector<std::vector<int>> components;
  int counter = 0;
  std::function<void(int)> connect = [&](int v) {
    const auto sv = static_cast<std::size_t>(v);
    index[sv] = low[sv] = counter++;
    stack.push_back(v);
    on_stack[sv] = 1;
    for (int w : edges[sv]) {
      const auto sw = static_cast<std::size_t>(w);
      if (index[sw] < 0) {
        connect(w);
        low[sv] = std::min(low[sv], low[sw]);
      } else if (on_stack[sw]) {
        low[sv] = std::min(low[sv], index[sw]);
      }
    }
    if (low[sv] == index[sv]) {
      std::vector<int> component;
      int w = -1;
      do {
        w = stack.back();
        stack.pop_back();
        on_stack[static_cast<std::size_t>(w)] = 0;
        component.push_back(w);
      } while (w != v);
      if (component.size() >= 2) components.push_back(std::move(component));
    }
  };
  for (std::size_t s = 0; s < n; ++s) {
    if (index[s] < 0 && slots_[s]->wait_since >= 0.0) connect(static_cast<int>(s));
  }
  for (auto& component : components) {
    // A member whose body stops another member's safety check is in the way itself: it yields
    // first (re-routing the stopped one would not move the body it stands behind). Then lowest
    // priority first.
    const auto stops_a_member = [&](const Robot& r) {
      return std::any_of(component.begin(), component.end(), [&](int m) {
        const auto& stopped_for = slots_[static_cast<std::size_t>(m)]->stopped_for;
        return std::binary_search(stopped_for.begin(), stopped_for.end(), r.id);
      });
    };
    std::vector<std::uint8_t> in_the_way(n, 0);
    for (int s : component) {
      in_the_way[static_cast<std::size_t>(s)] = stops_a_member(*slots_[static_cast<std::size_t>(s)]) ? 1 : 0;
    }
    std::sort(component.begin(), component.end(), [&](int a, int b) {
      if (in_the_way[static_cast<std::size_t>(a)] != in_the_way[static_cast<std::size_t>(b)]) {
        return in_the_way[static_cast<std::size_t>(a)] > in_the_way[static_cast<std::size_t>(b)];
      }
      return higher_priority(*slots_[static_cast<std::size_t>(b)], *slots_[static_cast<std::size_t>(a)]);
    });
    std::vector<int> ids;
    for (int s : component) ids.push_back(slots_[static_cast<std::size_t>(s)]->id);
    // The members a robot waits for, and the members waiting for it.
    const auto waiting = [&](const Robot& waiter, int for_id) {
      return std::find(waiter.blocked_by.begin(), waiter.blocked_by.end(), for_id) != waiter.blocked_by.end();
    };
    const auto blockers_of = [&](const Robot& victim) {
      std::vector<int> blockers;
      for (int id : ids) {
        if (id != victim.id && waiting(victim, id)) blockers.push_back(id);
      }
      return blockers;
    };
    // One instruction at a time: a member sent a new route that has not reached it yet may break
    // the cycle by what it does; and a robot just sent one is not picked again until it could act
    // on it (it may stand where it did for a moment, and a body it stopped may still be reported).
    const bool instructed =
        std::any_of(ids.begin(), ids.end(), [&](int id) { return robots_.at(id).pending != Instruction::kNone; });
    if (instructed) continue;
    // A member whose own safety check stops it for another member's body cannot drive a new
    // route from where it stands any more than its old one: it is sent nowhere until the others
    // have been tried and it has given its road back (each new route would also restart the
    // report of its stop, and the cycle would come back as often).
    const auto stopped_by_member = [&](const Robot& r) {
      return std::any_of(r.stopped_for.begin(), r.stopped_for.end(),
                         [&](int id) { return id != r.id && std::find(ids.begin(), ids.end(), id) != ids.end(); });
    };
    const auto send_one_away = [&](bool body_stopped) {
      for (int s : component) {
        Robot& victim = *slots_[static_cast<std::size_t>(s)];
        if (stopped_by_member(victim) != body_stopped) continue;
        // A robot standing beside the roads is never sent anywhere (it may be docking).
        if (victim.frozen || now - victim.last_reroute < kActOnInstruction) continue;
        // A member already yielding to it on a siding makes way for it: sending it off as well
        // would only swap who yields, again and again. Unless that member waits for it on the
        // way: then it makes way for nobody, and the robot it yields to is the one to move.
        const bool yielded_to = std::any_of(ids.begin(), ids.end(), [&](int id) {
          const Robot& other = robots_.at(id);
          return other.in_siding && !waiting(other, victim.id) &&
                 std::find(other.yield_to.begin(), other.yield_to.end(), victim.id) != other.yield_to.end();
        });
        if (yielded_to) continue;
        // It goes round the robots it waits for, or out of the way of the robots waiting for it.
        std::vector<int> waiters;
        for (int id : ids) {
          if (id != victim.id && waiting(robots_.at(id), victim.id)) waiters.push_back(id);
        }
        if (reroute(victim, blockers_of(victim), now, out, TrafficEvent::Kind::kDeadlockResolved) ||
            send_to_siding(victim, waiters, now, out, in_the_way[static_cast<std::size_t>(s)] != 0)) {
          return true;
        }
      }
      return false;
    };
    bool resolved = send_one_away(false);
    // A member whose safety check stops it for another member's body cannot use the road it holds
    // beyond where it stands; when the others wait for that road, it gives it back and waits
    // until those bodies have passed.
    for (std::size_t k = 0; !resolved && k < component.size(); ++k) {
      resolved = give_way(*slots_[static_cast<std::size_t>(component[k])], ids, now, out);
    }
    if (!resolved) resolved = send_one_away(true);
    // Last resort: a way round against a one-way corridor. Robots standing where the one-way
    // plan does not expect them (a map switch changed the corridors' directions) can face each
    // other with no way out along the plan; driving against it is safe, as nobody enters a
    // corridor towards a robot driving in it (place_free_for).
    for (std::size_t k = 0; !resolved && configuration_.one_way && k < component.size(); ++k) {
      Robot& victim = *slots_[static_cast<std::size_t>(component[k])];
      if (victim.frozen) continue;
      resolved = reroute(victim, blockers_of(victim), now, out, TrafficEvent::Kind::kDeadlockResolved, true);
    }
    if (!resolved) out.events.push_back({TrafficEvent::Kind::kUnresolvedDeadlock, now, ids.front(), ids});
  }
}

}  // namespace fleet::traffic
