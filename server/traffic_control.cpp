#include "server/traffic_control.hpp"

#include <algorithm>
#include <cmath>

#include "model/names.hpp"

namespace fleet::server {

namespace {
const char* status_name(traffic::GrantStatus s) {
  switch (s) {
    case traffic::GrantStatus::kMoving:
      return "MOVING";
    case traffic::GrantStatus::kWaiting:
      return "WAITING";
    case traffic::GrantStatus::kArrived:
      return "ARRIVED";
  }
  return "MOVING";
}

const char* instruction_name(traffic::Instruction i) {
  switch (i) {
    case traffic::Instruction::kNone:
      return "";
    case traffic::Instruction::kReroute:
      return "REROUTE";
    case traffic::Instruction::kSiding:
      return "SIDING";
  }
  return "";
}

}  // namespace

TrafficControl::TrafficControl(std::unique_ptr<traffic::TrafficManager> manager, std::string map_id,
                               dds::Participant& participant, SenderGate& gate, Logger log)
    : manager_(std::move(manager)),
      map_id_(std::move(map_id)),
      gate_(gate),
      log_(std::move(log)),
      grants_(participant, log_),
      requests_(participant, gate) {
  const auto& configuration = manager_->configuration();
  log_->info("traffic control on: {} places, lookahead {:.2f} m, one-way corridors {}", manager_->zones().place_count(),
             configuration.lookahead, configuration.one_way ? "on" : "off");
}

int TrafficControl::number_of(const std::string& robot_id) {
  auto it = numbers_.find(robot_id);
  if (it != numbers_.end()) return it->second;
  const int number = static_cast<int>(numbers_.size()) + 1;
  numbers_[robot_id] = number;
  names_[number] = robot_id;
  // Its fleet's vehicle type: which places conflict with its body, which lanes it fits.
  const auto& types = manager_->configuration().robot_vehicle_types;
  if (const auto type = types.find(robot_id); type != types.end()) manager_->set_robot_type(number, type->second);
  return number;
}

void TrafficControl::handle_requests(double now_sim, double now_wall) {
  // A new manager (start-up, map switch) first learns where every robot stands from their
  // states, so that nobody is admitted into another's body.
  constexpr double kSettleWall = 0.5;
  if (settle_until_wall_ < 0.0) settle_until_wall_ = now_wall + kSettleWall;
  if (now_wall < settle_until_wall_) return;
  requests_.take([&](model::TrafficRequest&& request, const dds::SampleInfo& info) {
    if (request.robot_id.empty() || !std::isfinite(request.progress)) {
      gate_.warn(info, "progress",
                 fmt::format("traffic request from '{}' ignored: progress {} is not a number", request.robot_id,
                             request.progress));
      return;
    }
    if (request.map_id != map_id_) {
      // Sent before the robot heard of a map switch: its points number another graph, whose
      // places would be held and granted for a way it does not drive. Until it replans on this
      // map it stands for the places its body touches, as one not heard from.
      if (other_map_.insert(request.robot_id).second) {
        log_->info("traffic: {} still drives on map '{}'; its requests wait until it replans on '{}'", request.robot_id,
                   request.map_id, map_id_);
      }
      return;
    }
    other_map_.erase(request.robot_id);
    heard_.insert(request.robot_id);
    const auto bad_point = std::find_if(request.points.begin(), request.points.end(), [&](int point) {
      return point < 0 || static_cast<std::size_t>(point) >= manager_->zones().point_count();
    });
    if (bad_point != request.points.end()) {
      gate_.warn(info, "point",
                 fmt::format("traffic request from '{}' ignored: graph point {} does not exist ({} points)",
                             request.robot_id, *bad_point, manager_->zones().point_count()));
      return;
    }
    const int id = number_of(request.robot_id);
    if (request.points.empty()) {
      // Off the roads. Working at a loading area its body still reaches onto the lane: it holds
      // the places its body touches, so nobody is granted up to it (a robot stopped there by the
      // agents' safety check would hold the entry it needs to leave by). Parked at a home, clear
      // of the lanes, it holds nothing.
      manager_->drop_entry(id);
      status_.erase(request.robot_id);
      if (!request.work_area.empty()) {
        work_beside_roads(request, id, now_sim, now_wall);
        return;
      }
      working_.erase(request.robot_id);
      const bool was_on_roads = manager_->has_robot(id);
      if (stand_where_it_is(request.robot_id, id, now_sim)) {
        // Docked, it will turn out across the lanes: nobody is to stop in its way meanwhile.
        manager_->keep_clear(
            id, request.keep_clear.empty() ? geometry::Polygon{} : traffic::convex_hull(request.keep_clear));
        log_->debug("{} works beside the roads, holding the {} places its body touches{}", request.robot_id,
                    manager_->held_places(id).size(), request.keep_clear.empty() ? "" : ", its way out kept clear");
      } else if (was_on_roads) {
        log_->debug("{} left the roads", request.robot_id);
      }
      return;
    }
    working_.erase(request.robot_id);
    bool standing = manager_->frozen(id);
    bool enter = !manager_->has_robot(id) || standing;
    if (!enter && request.version > manager_->version(id)) {
      // A new route from where it is. It starts somewhere it does not hold when it drove off the
      // graph and came back elsewhere, or replanned beside the road before it set off (an
      // obstacle toggled): then it enters afresh there. Its old route is void: kept, it would go
      // on being granted while the robot waits to enter, and hold others up for a route nobody
      // drives. The robot stands where its body is until it is let in, as one beside the road.
      const auto result = manager_->submit_route({id, request.version, request.points}, now_sim);
      if (result == traffic::SubmitStatus::kInvalid) {
        const std::uint64_t dropped = manager_->version(id);
        standing = stand_where_it_is(request.robot_id, id, now_sim, /*keep_turn=*/true);
        enter = true;
        log_->debug("traffic: {} route {} starts where it does not stand; route {} dropped, it enters afresh",
                    request.robot_id, request.version, dropped);
      }
      if (result == traffic::SubmitStatus::kAccepted) trims_.erase(request.robot_id);
    }
    // Leaving a dock or a bay, a robot that sweeps across the lane turning onto it (a stacker)
    // sends the area of that way out: it enters once nobody holds or stands in it, and holds it
    // as it enters (its route keeps those places until it is past the route's first edge).
    if (enter && standing && !request.work_area.empty() && !way_out_clear(request, id, now_sim, now_wall)) return;
    if (enter) {
      // A robot already part-way along its route (the server restarted under it, or it was
      // lost and came back) enters where it is: the points behind it are cut off, and its
      // progress and grants are shifted by what was cut (trims_).
      traffic::RouteRequest route{id, request.version, request.points};
      const auto [skip, offset] = manager_->entry_point(id, request.points, request.progress);
      route.points.erase(route.points.begin(), route.points.begin() + static_cast<std::ptrdiff_t>(skip));
      if (skip > 0) {
        trims_[request.robot_id] = {request.version, static_cast<int>(skip), offset};
      } else {
        trims_.erase(request.robot_id);
      }
      // Entering the roads: at once where its body already stands (it holds that place), else
      // only where no one holds a place in conflict with the entry; until then it waits beside
      // the road (granted_index -1), keeping what its body stands on.
      // Part-way along its route it stands on the road: its body holding the entry's place is enough.
      const bool already_there = standing && (stands_at(request.robot_id, id, route.points.front()) ||
                                              (skip > 0 && manager_->holds_place_of(id, route.points.front())));
      if (!already_there) {
        const auto entry = manager_->entry_for(route.points.front(), id, now_sim);
        const auto& holders = entry.blockers;
        if (!holders.empty()) {
          manager_->claim_entry(id, route.points.front(), now_sim);
          std::vector<std::string> blockers;
          for (int h : holders) blockers.push_back(names_[h]);
          wait_to_enter(request, std::move(blockers), now_sim, now_wall);
          return;
        }
        if (!entry.as_standing) manager_->remove_robot(id, now_sim);
      }
      const auto result = manager_->submit_route(route, now_sim);
      if (result != traffic::SubmitStatus::kAccepted) {
        log_->warn("route {} of {} refused ({} points from {})", request.version, request.robot_id,
                   request.points.size(), request.points.front());
        return;
      }
      manager_->drop_entry(id);
      held_bodies_.erase(request.robot_id);
      if (standing) {
        log_->debug("traffic: {} enters at {:.2f} m along route {} from where it stands", request.robot_id,
                    request.progress, request.version);
      }
    }
    log_->debug("traffic request {} v{} {} points progress {:.3f} (manager v{})", request.robot_id, request.version,
                request.points.size(), request.progress, manager_->version(id));
    double progress = request.progress;
    if (auto t = trims_.find(request.robot_id); t != trims_.end() && t->second.version == request.version) {
      progress -= t->second.offset;
    }
    std::vector<int> stopped_for;
    for (const auto& other : request.stopped_for) {
      if (auto known = numbers_.find(other); known != numbers_.end() && known->second != id) {
        stopped_for.push_back(known->second);
      }
    }
    manager_->report_progress({id, request.version, progress, std::move(stopped_for)}, now_sim);
    // Turning off its route's end into a place beside the road, it sweeps more than the lane.
    manager_->set_arrival_area(
        id, request.points.back(),
        request.arrival_area.empty() ? geometry::Polygon{} : traffic::convex_hull(request.arrival_area));
  });
}

void TrafficControl::robot_lost(const std::string& robot_id, const geometry::Polygon& body, double now_sim) {
  // Lost in the middle of a manoeuvre beside the roads, it may be heard from again any moment and
  // go on with it: it keeps the whole area the manoeuvre sweeps, or a robot granted into that area
  // meanwhile and the manoeuvring one would each stand in the other's way.
  const auto held = held_bodies_.find(robot_id);
  const bool manoeuvring = working_.contains(robot_id) && held != held_bodies_.end();
  const geometry::Polygon kept = manoeuvring ? held->second : body;
  auto it = numbers_.find(robot_id);
  if (it != numbers_.end()) manager_->drop_entry(it->second);
  if (it != numbers_.end() && manager_->freeze_robot(it->second, kept, now_sim)) {
    held_bodies_[robot_id] = kept;
    log_->warn("traffic: {} lost; it keeps the places its {} ({}), the rest is freed", robot_id,
               manoeuvring ? "manoeuvre sweeps" : "body stands on", manager_->held_places(it->second).size());
  }
  status_.erase(robot_id);
  // Its next grant goes out at once when it is back: it stands until one comes.
  grants_.forget(robot_id);
  if (!manoeuvring) working_.erase(robot_id);
}

bool TrafficControl::stands_at(const std::string& robot_id, int id, int point) const {
  // Its body holds the point's place, and it stands on the point, not merely beside its region.
  constexpr double kOnPointM = 0.15;
  if (!manager_->holds_place_of(id, point)) return false;
  auto body = bodies_.find(robot_id);
  if (body == bodies_.end() || body->second.empty()) return false;
  const geometry::Vec2 centre = geometry::vertex_centroid(body->second);
  const auto& at = manager_->route_graph().points[static_cast<std::size_t>(point)];
  return geometry::distance(centre, {at.x, at.y}) <= kOnPointM;
}

void TrafficControl::work_beside_roads(const model::TrafficRequest& request, int id, double now_sim, double now_wall) {
  // A manoeuvre beside the roads sweeps more than the body: it starts once no other robot holds a
  // place the swept area touches, and the area stays held until it ends, so nobody is granted
  // into it meanwhile. Two manoeuvres whose areas touch take turns.
  // The area it sweeps must be clear; the body it stands with is held with it, but robots queued
  // up behind that body (waiting for it) do not keep it from starting.
  const geometry::Polygon swept = traffic::convex_hull(request.work_area);
  const geometry::Polygon area = area_with_body(request);
  model::TrafficGrant answer;
  answer.robot_id = request.robot_id;
  answer.version = request.version;
  answer.sim_time = now_sim;
  if (!working_.contains(request.robot_id)) {
    const std::vector<int> blockers = robots_in_area(id, swept);
    if (!blockers.empty()) {
      if (!manager_->frozen(id)) stand_where_it_is(request.robot_id, id, now_sim);
      manager_->wait_for_area(id, blockers);
      answer.status = "AREA_WAITING";
      for (int b : blockers) answer.blocked_by.push_back(names_[b]);
      // Known as waiting for them: a robot whose way out onto the road it stands in goes first.
      status_[request.robot_id] = {"AREA_WAITING", 0.0, answer.blocked_by, {}};
      grants_.publish(std::move(answer), now_wall);
      return;
    }
    working_.insert(request.robot_id);
    manager_->wait_for_area(id, {});
    log_->debug("traffic: {} manoeuvres beside the roads", request.robot_id);
  }
  if (manager_->has_robot(id) && !manager_->frozen(id)) manager_->remove_robot(id, now_sim);
  hold_body(request.robot_id, id, area, now_sim);
  answer.status = "AREA_CLEAR";
  grants_.publish(std::move(answer), now_wall);
}

geometry::Polygon TrafficControl::area_with_body(const model::TrafficRequest& request) const {
  std::vector<geometry::Vec2> corners = request.work_area;
  if (const auto body = bodies_.find(request.robot_id); body != bodies_.end()) {
    corners.insert(corners.end(), body->second.begin(), body->second.end());
  }
  return traffic::convex_hull(std::move(corners));
}

void TrafficControl::wait_to_enter(const model::TrafficRequest& request, std::vector<std::string> blockers,
                                   double now_sim, double now_wall) {
  model::TrafficGrant wait;
  wait.robot_id = request.robot_id;
  wait.version = request.version;
  wait.granted_index = -1;
  wait.status = "WAITING";
  wait.blocked_by = blockers;
  wait.sim_time = now_sim;
  status_[request.robot_id] = {"WAITING", 0.0, std::move(blockers), {}};
  grants_.publish(std::move(wait), now_wall);
}

void TrafficControl::set_partners(std::map<std::string, std::string> partners) {
  std::set<std::pair<int, int>> pairs;
  for (const auto& [a, b] : partners) {
    const auto first = numbers_.find(a);
    const auto second = numbers_.find(b);
    // A transporter whose picker is not known yet (empty) pairs with none: -1.
    if (first != numbers_.end() && (b.empty() || second != numbers_.end())) {
      pairs.insert({first->second, b.empty() ? -1 : second->second});
    }
  }
  manager_->set_partners(std::move(pairs));
  TrafficService::set_partners(std::move(partners));
}

std::vector<int> TrafficControl::robots_in_area(int id, const geometry::Polygon& area) const {
  // A standing robot counts by what traffic holds for it: its body, or the area of its manoeuvre.
  std::map<int, geometry::Polygon> bodies;
  for (const auto& [name, polygon] : bodies_) {
    const auto number = numbers_.find(name);
    if (number == numbers_.end()) continue;
    const auto held = held_bodies_.find(name);
    const bool standing = manager_->frozen(number->second) && held != held_bodies_.end();
    bodies[number->second] = standing ? held->second : polygon;
  }
  std::vector<int> holders = manager_->holders_in_area(id, area, bodies);
  std::erase_if(holders, [&](int h) { return partners(names_.at(h), names_.at(id)); });
  return holders;
}

bool TrafficControl::way_out_clear(const model::TrafficRequest& request, int id, double now_sim, double now_wall) {
  const geometry::Polygon swept = traffic::convex_hull(request.work_area);
  std::vector<std::string> blockers;
  std::vector<int> blocker_ids;
  for (int b : robots_in_area(id, swept)) {
    // A robot that waits for this one's body stands clear of it; if it stands in the way out,
    // this one's own checks stop it there, and the wait cycle that makes is broken by traffic.
    const auto waits = status_.find(names_[b]);
    const bool waits_for_it =
        waits != status_.end() && std::find(waits->second.blocked_by.begin(), waits->second.blocked_by.end(),
                                            request.robot_id) != waits->second.blocked_by.end();
    if (!waits_for_it) {
      blockers.push_back(names_[b]);
      blocker_ids.push_back(b);
    }
  }
  manager_->wait_for_area(id, blocker_ids);
  if (!blockers.empty()) {
    wait_to_enter(request, std::move(blockers), now_sim, now_wall);
    return false;
  }
  hold_body(request.robot_id, id, area_with_body(request), now_sim);
  return true;
}

void TrafficControl::set_body(const std::string& robot_id, const geometry::Polygon& body) {
  const auto [known, first] = bodies_.try_emplace(robot_id);
  if (first) grants_.open(robot_id);
  known->second = body;
}

bool TrafficControl::hold_body(const std::string& robot_id, int id, const geometry::Polygon& body, double now_sim) {
  // Finding the places under a body costs a pass over every place: only when it moved.
  constexpr double kMovedM = 0.01;
  auto held = held_bodies_.find(robot_id);
  const bool moved = held == held_bodies_.end() || !geometry::same_polygon(held->second, body, kMovedM);
  if (!moved && manager_->has_robot(id) == manager_->frozen(id)) return manager_->frozen(id);
  held_bodies_[robot_id] = body;
  return manager_->hold_body(id, body, now_sim);
}

bool TrafficControl::stand_where_it_is(const std::string& robot_id, int id, double now_sim, bool keep_turn) {
  const geometry::Polygon turn = keep_turn ? manager_->turn_area(id) : geometry::Polygon{};
  manager_->remove_robot(id, now_sim);
  held_bodies_.erase(robot_id);  // held anew from where it stands now
  const auto body = bodies_.find(robot_id);
  if (body == bodies_.end()) return false;
  if (turn.empty()) return hold_body(robot_id, id, body->second, now_sim);
  // Still in the place it turned into: its way back onto the road sweeps the same area.
  std::vector<geometry::Vec2> corners = turn;
  corners.insert(corners.end(), body->second.begin(), body->second.end());
  return hold_body(robot_id, id, traffic::convex_hull(std::move(corners)), now_sim);
}

void TrafficControl::note_stuck_cycle(const traffic::TrafficEvent& e, const std::string& others, double now_sim) {
  // A wait cycle the manager cannot break in this long is worth a warning: the soak counts its
  // robots as deadlocked after 60 s, and the log then says who waits for whom, along which routes.
  constexpr double kReportStuckCycleAfter = 30.0;  // sim s
  // Members sorted: the same cycle found from another member is the same cycle.
  std::vector<std::string> sorted;
  for (int o : e.others) sorted.push_back(names_[o]);
  std::sort(sorted.begin(), sorted.end());
  StuckCycle& cycle = stuck_cycles_.try_emplace(model::join(sorted), StuckCycle{now_sim, now_sim, false}).first->second;
  cycle.last_seen = now_sim;
  const bool report = !cycle.reported && now_sim - cycle.since >= kReportStuckCycleAfter;
  // Found again every cycle while it lasts: described only when it is logged.
  if (!report && !log_->should_log(spdlog::level::debug)) return;
  std::string members;
  for (int o : e.others) {
    const auto& route = manager_->route(o);
    if (route.empty()) continue;
    const auto from = manager_->zones().position(manager_->zones().place_of(route.front()));
    const auto to = manager_->zones().position(manager_->zones().place_of(route.back()));
    const auto status = status_.find(names_[o]);
    const std::string waits_for = status != status_.end() ? model::join(status->second.blocked_by, " ") : "";
    members += fmt::format(" {}: ({:.2f}, {:.2f}) -> ({:.2f}, {:.2f}), {} points, holds {}, waits for [{}];", names_[o],
                           from.x, from.y, to.x, to.y, route.size(), manager_->held_places(o).size(), waits_for);
  }
  if (report) {
    cycle.reported = true;
    log_->warn("traffic: wait cycle [{}] has had no way out for {:.0f} s:{}", others, now_sim - cycle.since, members);
  } else {
    log_->debug("traffic: wait cycle [{}] has no way out yet:{}", others, members);
  }
}

void TrafficControl::update(double now_sim, double now_wall) {
  constexpr double kForgetCycleAfter = 5.0;  // sim s without a stuck cycle: broken, or other members
  // Robots not heard from yet (the manager just started among them) hold what their bodies
  // stand on, before anyone is granted more; so do lost ones (robot_lost). A robot working
  // beside the roads holds the area of its manoeuvre, renewed by its requests: held as its body
  // alone here, the area opened to others between two requests.
  for (const auto& [robot_id, body] : bodies_) {
    const int id = number_of(robot_id);
    if (heard_.contains(robot_id) && working_.contains(robot_id)) {
      // Lost during a manoeuvre, it kept the manoeuvre's area (robot_lost). Back with its body
      // outside that area, its agent started again elsewhere (at its home): the manoeuvre is
      // over, and it holds what its body stands on, as any robot not working.
      const auto kept = held_bodies_.find(robot_id);
      if (kept == held_bodies_.end() || !manager_->frozen(id) ||
          geometry::contains(kept->second, geometry::vertex_centroid(body))) {
        continue;
      }
      working_.erase(robot_id);
      log_->info("traffic: {} is back away from the manoeuvre it was lost in; the area it kept is freed", robot_id);
    }
    if (!heard_.contains(robot_id) || manager_->frozen(id)) hold_body(robot_id, id, body, now_sim);
  }
  const traffic::UpdateResult result = manager_->update(now_sim);
  for (const auto& e : result.events) {
    std::string others;
    for (int o : e.others) others += (others.empty() ? "" : ", ") + names_[o];
    const std::string& robot = names_[e.robot_id];
    switch (e.kind) {
      case traffic::TrafficEvent::Kind::kDeadlockResolved:
        log_->info("traffic: wait cycle [{}] broken by re-routing {}", others, robot);
        break;
      case traffic::TrafficEvent::Kind::kRerouted:
        log_->info("traffic: {} re-routed around {}", robot, others);
        break;
      case traffic::TrafficEvent::Kind::kSidingSent: {
        const auto& route = manager_->route(e.robot_id);
        if (route.empty()) {
          log_->info("traffic: {} yields on a siding to {}", robot, others);
          break;
        }
        const auto& zones = manager_->zones();
        const auto from = zones.position(zones.place_of(route.front()));
        const auto to = zones.position(zones.place_of(route.back()));
        log_->info("traffic: {} yields on a siding to {}: from ({:.2f}, {:.2f}) to ({:.2f}, {:.2f})", robot, others,
                   from.x, from.y, to.x, to.y);
        break;
      }
      case traffic::TrafficEvent::Kind::kGaveWay:
        log_->info("traffic: {} stands for {} and gives back the road ahead of it", robot, others);
        break;
      case traffic::TrafficEvent::Kind::kResumed:
        log_->info("traffic: {} leaves its siding", robot);
        break;
      case traffic::TrafficEvent::Kind::kRobotRemoved:
        break;
      case traffic::TrafficEvent::Kind::kUnresolvedDeadlock:
        note_stuck_cycle(e, others, now_sim);
        break;
    }
  }
  std::erase_if(stuck_cycles_, [&](const auto& entry) { return now_sim - entry.second.last_seen > kForgetCycleAfter; });
  for (const traffic::Grant& g : result.grants) {
    const std::string& robot = names_[g.robot_id];
    if (manager_->frozen(g.robot_id)) {
      // Standing where it is (parked, lost, or not admitted yet): nothing to grant, its places shown.
      auto& status = status_[robot];
      // Waiting to enter or for its work area: keeps who it waits for.
      if (status.status == "WAITING" || status.status == "AREA_WAITING") continue;
      status = {"STANDING", 0.0, {}, {}};
      for (int place : manager_->held_places(g.robot_id)) status.held.push_back(manager_->zones().position(place));
      continue;
    }
    model::TrafficGrant grant;
    grant.robot_id = robot;
    grant.version = g.version;
    grant.granted_index = g.granted_index;
    grant.granted_distance = g.granted_distance;
    if (auto t = trims_.find(robot); t != trims_.end() && t->second.version == g.version) {
      // In the robot's terms: along the whole route it reported.
      grant.granted_index += t->second.skipped;
      grant.granted_distance += t->second.offset;
    }
    grant.status = status_name(g.status);
    grant.waited_s = g.waited_s;
    for (int b : g.blocked_by) grant.blocked_by.push_back(names_[b]);
    grant.instruction = instruction_name(g.instruction);
    if (g.instruction != traffic::Instruction::kNone) grant.route = g.route;
    grant.sim_time = now_sim;
    auto& status = status_[robot];
    status.status = grant.status;
    status.waited_s = grant.waited_s;
    status.blocked_by = grant.blocked_by;
    status.held.clear();
    for (int place : manager_->held_places(g.robot_id)) status.held.push_back(manager_->zones().position(place));
    grants_.publish(std::move(grant), now_wall);
  }
}

}  // namespace fleet::server
