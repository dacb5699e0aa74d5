// PlaceTraffic's plan steps, re-routes and grants.
#include <algorithm>
#include <cmath>

#include "coordination/place_traffic.hpp"

namespace fleet::coordination {

void PlaceTraffic::update(double now) {
  if (closed_stale_) rebuild_closed();
  for (int robot = 0; robot < robots(); ++robot) {
    if (at(robot).mode == Mode::kWaitingToEnter) try_to_enter(robot);
  }
  if (now >= next_plan_) {
    plan_step();
    next_plan_ = now + params_.plan_period_s;
  }
  for (int robot = 0; robot < robots(); ++robot) update_grant(robot);
}

void PlaceTraffic::reserve_entries() {
  for (int robot = 0; robot < robots(); ++robot) {
    Robot& r = at(robot);
    const auto waits_for_it = [&](int other) {
      const auto& waits = at(other).grant.waits_for;
      return std::find(waits.begin(), waits.end(), robot) != waits.end();
    };
    // Once it holds its way, it holds it until it enters: the robots it pushes out of it wait for
    // others on the way out, not for its body, and would come straight back in.
    const bool reserves =
        r.mode == Mode::kWaitingToEnter && r.way_out.empty() &&
        (r.reserves_entry || std::any_of(r.entry_blockers.begin(), r.entry_blockers.end(), waits_for_it));
    if (reserves != r.reserves_entry) closed_stale_ = true;
    r.reserves_entry = reserves;
  }
  if (closed_stale_) rebuild_closed();
}

void PlaceTraffic::plan_step() {
  reserve_entries();
  // A robot's visits from the first that waits for another robot's on are not granted: planned
  // again each step from its last granted one, they stay as they were, or the planner sends it
  // another way or pushes it. Kept, a robot whose plan ran ahead behind another would be held
  // behind its own plan, and the other could never get past those visits.
  // A robot its own look-ahead stops for another's body cannot make its visits: those not begun
  // go, so that robots whose visits wait for them may go first and take their bodies away.
  // A visit granted stays: the robot may be in it already, the grant having reached it before its
  // report of the move reaches traffic. One stopped reported where it stands, and stands.
  for (int robot = 0; robot < robots(); ++robot) {
    if (at(robot).mode != Mode::kDriving || !order_.present(robot)) continue;
    const int not_begun = order_.has_left(robot) ? 2 : 1;
    const bool stopped = !at(robot).stopped_for.empty();
    const int first_droppable = stopped ? not_begun : std::max(not_begun, granted_visits(at(robot)) + 1);
    for (int k = first_droppable; k <= order_.pending(robot); ++k) {
      if (stopped || order_.waits_for(robot, k) >= 0) {
        order_.drop_from(robot, k);
        break;
      }
    }
  }
  // The plan runs ahead of the robots: each is planned from the last place planned for it,
  // along its route where the route leads on.
  std::vector<PlaceRobot> planned(robots_.size());
  for (int robot = 0; robot < robots(); ++robot) {
    const Robot& r = at(robot);
    PlaceRobot& p = planned[static_cast<std::size_t>(robot)];
    p.type = r.type;
    if (r.mode != Mode::kDriving || !order_.present(robot)) {
      p.place = -1;
      // Standing beside the roads, waiting for the area of its manoeuvre: it clears it.
      p.pushes_from_area = r.mode == Mode::kStanding && !r.way_out.empty();
      // A robot waiting to enter with a way out pushes those in it out of it; one without pushes
      // those in its way once one of them waits for it in turn (its body closes their way on),
      // holding where it enters (reserve_entries), and else waits for them to drive on.
      if (r.mode == Mode::kWaitingToEnter && (!r.way_out.empty() || r.reserves_entry)) {
        p.entering = r.places[static_cast<std::size_t>(r.index_at(r.progress))];
      }
      continue;
    }
    p.place = order_.last_planned(robot);
    const auto last = static_cast<std::size_t>(r.at + order_.pending(robot));
    const bool at_end = last + 1 >= r.places.size();
    // Stopped for another's body, it has no errand for now: it stays, unless a robot that needs
    // its place pushes it out of the way (its look-ahead lets it drive away from the body it
    // stopped for, never towards it).
    const bool stopped = !r.stopped_for.empty();
    p.goal = stopped ? -1 : at_end ? r.places.back() : r.places[r.leg_end(last)];
    p.preferred = stopped || at_end ? -1 : r.places[last + 1];
    // Behind its plan, waiting for a new route to reach it, not yet where a move off its route
    // (a push, giving way) puts it, or at its route's end (where it turns off the road): planned
    // to stay, never pushed. Planned on from a push it has not made, a robot comes straight back
    // in the next step, before the robot that pushed it has taken the room: each step pushes it
    // again, and its route shuttles between two places.
    p.held = !r.adopted || (!stopped && order_.pending(robot) >= params_.plan_ahead) ||
             (r.moved_off_route && order_.pending(robot) > 0) || at_end;
  }
  const std::vector<int> next = planner_.plan(planned, &closures_.closed());
  ++plan_step_;
  // Who stands and who goes where, by place: a robot kept standing looks up those in its way
  // among the places conflicting with its next one rather than asking every robot.
  std::vector<int> stands(zones_.place_count(), -1);
  std::vector<int> goes(zones_.place_count(), -1);
  for (std::size_t i = 0; i < planned.size(); ++i) {
    if (planned[i].place < 0) continue;
    stands[static_cast<std::size_t>(planned[i].place)] = static_cast<int>(i);
    if (next[i] >= 0) goes[static_cast<std::size_t>(next[i])] = static_cast<int>(i);
  }
  for (int robot = 0; robot < robots(); ++robot) at(robot).kept_by = kept_by(robot, planned, next, stands, goes);
  for (int robot = 0; robot < robots(); ++robot) {
    const PlaceRobot& p = planned[static_cast<std::size_t>(robot)];
    const int to = next[static_cast<std::size_t>(robot)];
    if (p.place < 0 || to == p.place) continue;
    const int pending = order_.pending(robot);
    if (pending >= 1 && to == order_.visit_place(robot, pending - 1) && (pending >= 2 || !order_.has_left(robot)) &&
        pending > granted_visits(at(robot))) {
      // Pushed back out of its last planned place before it began that visit: the visit goes,
      // instead of a move back. Planned as a move, its route would go on, back and on again
      // over the same ground.
      order_.drop_from(robot, pending);
      continue;
    }
    order_.plan(robot, to, plan_step_);
    // The end of each leg is a goal reached: its priority starts over, as at the route's end.
    if (to == p.goal) planner_.reached_goal(robot);
    at(robot).moved_off_route = to != p.preferred;
    if (to != p.preferred) reroute(robot);
  }
}

std::vector<int> PlaceTraffic::kept_by(int robot, const std::vector<PlaceRobot>& planned, const std::vector<int>& next,
                                       const std::vector<int>& stands, const std::vector<int>& goes) const {
  const PlaceRobot& p = planned[static_cast<std::size_t>(robot)];
  if (p.place < 0 || p.preferred < 0 || p.held || next[static_cast<std::size_t>(robot)] != p.place) return {};
  std::vector<int> in_the_way;
  for (int other_type = 0; other_type < static_cast<int>(zones_.type_count()); ++other_type) {
    for (const int q : zones_.conflicts(p.type, p.preferred, other_type)) {
      for (const int other : {stands[static_cast<std::size_t>(q)], goes[static_cast<std::size_t>(q)]}) {
        if (other >= 0 && other != robot && planned[static_cast<std::size_t>(other)].type == other_type) {
          in_the_way.push_back(other);
        }
      }
    }
  }
  std::sort(in_the_way.begin(), in_the_way.end());
  in_the_way.erase(std::unique(in_the_way.begin(), in_the_way.end()), in_the_way.end());
  return in_the_way;
}

int PlaceTraffic::granted_visits(const Robot& r) {
  const PlaceGrant& g = r.grant;
  if (g.version != r.version || g.granted_index < 0) return 0;
  for (std::size_t index = static_cast<std::size_t>(r.at); index < r.place_point.size(); ++index) {
    if (r.place_point[index] == g.granted_index) return static_cast<int>(index) - r.at;
  }
  return 0;
}

void PlaceTraffic::reroute(int robot) {
  Robot& r = at(robot);
  std::vector<int> places;
  for (int k = 0; k <= order_.pending(robot); ++k) places.push_back(order_.visit_place(robot, k));
  // On from the last planned place along a shortest way to the route's end.
  const int goal = r.places.back();
  for (int guard = 0; places.back() != goal && guard < static_cast<int>(zones_.place_count()); ++guard) {
    const int from = places.back();
    int best = -1;
    double best_metres = PlaceGraph::kUnreachable;
    for (const int next : places_.successors(r.type, from)) {
      const double metres = places_.step_length(from, next) + places_.distance(r.type, next, goal);
      if (metres < best_metres) {
        best_metres = metres;
        best = next;
      }
    }
    if (best < 0) break;
    places.push_back(best);
  }
  const std::vector<int> points = points_along(first_point(r, places.front()), places);
  if (points.empty()) return;
  // Odd: the robots' own routes take even versions, so a second new route handed before the
  // robot took the first never gets the version of the robot's next own route.
  r.version = (r.version + 1) | 1U;
  r.assign(graph_, zones_, points);
  r.at = 0;
  r.adopted = false;
}

int PlaceTraffic::first_point(const Robot& r, int place) const {
  // The point of the route the robot drives when it is of `place`; else the point of `place`
  // nearest the route's point at the robot's place.
  const int route_point = r.points[static_cast<std::size_t>(r.place_point[static_cast<std::size_t>(r.at)])];
  if (r.places[static_cast<std::size_t>(r.at)] == place) return route_point;
  const auto& candidates = points_of_place_[static_cast<std::size_t>(place)];
  const auto& from = graph_.points[static_cast<std::size_t>(route_point)];
  const auto metres = [&](int point) {
    const auto& p = graph_.points[static_cast<std::size_t>(point)];
    return std::hypot(p.x - from.x, p.y - from.y);
  };
  return *std::min_element(candidates.begin(), candidates.end(), [&](int a, int b) { return metres(a) < metres(b); });
}

std::vector<int> PlaceTraffic::points_along(int from_point, const std::vector<int>& places) const {
  // Between two places an edge of the road graph either way (a robot pushed backs up against its
  // lane), from the point reached or one coincident with it (a road hand-over).
  std::vector<int> points{from_point};
  for (std::size_t k = 1; k < places.size(); ++k) {
    const auto& here = points_of_place_[static_cast<std::size_t>(places[k - 1])];
    const auto& there = points_of_place_[static_cast<std::size_t>(places[k])];
    auto linked = [&](int a, int b) {
      const auto& out = graph_.successors[static_cast<std::size_t>(a)];
      return std::find(out.begin(), out.end(), b) != out.end();
    };
    int via = -1;
    int to = -1;
    for (const int u : here) {
      for (const int v : there) {
        if (linked(u, v) || linked(v, u)) {
          const bool better = via < 0 || (u == points.back() && via != points.back());
          if (better) {
            via = u;
            to = v;
          }
        }
      }
    }
    if (to < 0) return {};
    if (via != points.back()) points.push_back(via);
    points.push_back(to);
  }
  return points;
}

void PlaceTraffic::update_grant(int robot) {
  Robot& r = at(robot);
  PlaceGrant& g = r.grant;
  g.version = r.version;
  g.waits_for.clear();
  g.arrived = false;
  g.granted_index = -1;
  g.granted_distance = 0.0;
  g.route.clear();
  if (r.mode == Mode::kWaitingToEnter) {
    g.waits_for = r.entry_blockers;
    return;
  }
  if (r.mode != Mode::kDriving) return;
  // Up to the last visit none of whose earlier conflicting visits is open: those that ended stay
  // ended, so the robot may drive on through them without stopping.
  int k = order_.has_left(robot) ? 1 : 0;
  while (k < order_.pending(robot)) {
    const int other = order_.waits_for(robot, k + 1);
    if (other >= 0) {
      g.waits_for.push_back(other);
      break;
    }
    ++k;
  }
  const auto index = static_cast<std::size_t>(r.at + k);
  if (g.waits_for.empty() && k == order_.pending(robot) && index + 1 < r.places.size()) {
    // Its route leads on into a place a body or a way out closes: it waits for those robots.
    g.waits_for = closers_of(robot, r.type, r.places[index + 1], r.places[index]);
  }
  // The plan keeps it standing where its route leads on into robots' places.
  if (g.waits_for.empty() && k == order_.pending(robot)) g.waits_for = r.kept_by;
  if (g.waits_for.empty()) g.waits_for = r.stopped_for;
  g.granted_index = r.place_point[index];
  g.granted_distance = r.point_s[static_cast<std::size_t>(g.granted_index)];
  g.arrived = static_cast<std::size_t>(r.at) + 1 == r.places.size();
  if (!r.adopted) g.route = r.points;
}

}  // namespace fleet::coordination
