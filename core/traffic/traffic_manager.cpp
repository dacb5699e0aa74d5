#include "traffic/traffic_manager.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <sstream>
#include <stdexcept>

#include "traffic/traffic_manager_detail.hpp"

namespace fleet::traffic {

using detail::kInfinity;
using detail::sort_unique;

namespace {

void check_positive(double value, const char* key) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string("traffic configuration: ") + key + " must be a positive number, got " +
                                std::to_string(value));
  }
}

}  // namespace

TrafficManager::TrafficManager(const map::RoadGraph& graph, const TrafficConfiguration& configuration)
    : configuration_(configuration), graph_(graph) {
  check_positive(configuration.lookahead, "lookahead");
  check_positive(configuration.priority_wait, "priority_wait");
  check_positive(configuration.reroute_wait, "reroute_wait");
  check_positive(configuration.lost_reroute_wait, "lost_reroute_wait");
  check_positive(configuration.yield_timeout, "yield_timeout");
  check_positive(configuration.siding_window, "siding_window");
  if (!(configuration.release_margin >= 0.0))
    throw std::invalid_argument("traffic configuration: release_margin must be >= 0");
  if (!(configuration.stop_tolerance >= 0.0))
    throw std::invalid_argument("traffic configuration: stop_tolerance must be >= 0");
  zones_ = std::make_unique<ConflictZones>(graph_, configuration.resources);
  // Finding the places under a body tests it against every region: their boxes first.
  region_bounds_.resize(zones_->place_count() * zones_->type_count());
  for (std::size_t t = 0; t < zones_->type_count(); ++t) {
    for (std::size_t p = 0; p < zones_->place_count(); ++p) {
      std::vector<geometry::Vec2> corners;
      for (const auto& piece : zones_->region(static_cast<int>(t), static_cast<int>(p))) {
        corners.insert(corners.end(), piece.begin(), piece.end());
      }
      region_bounds_[typed(static_cast<int>(t), static_cast<int>(p))] = geometry::bounding_box(corners);
    }
  }
  search_ = std::make_unique<RouteSearch>(graph_, *zones_);
  if (configuration.one_way) one_way_ = one_way_plan(graph_, *zones_);
  // One one-way plan for every type, so robots of different types agree on each corridor's
  // direction; each type then keeps only the lanes it fits.
  const map::RoadGraph& shared = configuration.one_way ? one_way_.graph : graph_;
  for (const VehicleType& type : zones_->vehicle_types()) {
    const double width = footprint_width(type.footprint);
    auto graphs = std::make_unique<TypeGraphs>();
    graphs->lanes = lane_graph_for(graph_, width, configuration.resources.margin);
    graphs->route = lane_graph_for(shared, width, configuration.resources.margin);
    graphs->search = std::make_unique<RouteSearch>(graphs->lanes, *zones_);
    graphs->route_search = std::make_unique<RouteSearch>(graphs->route, *zones_);
    types_.push_back(std::move(graphs));
  }
}

bool TrafficManager::set_robot_type(int robot_id, int type) {
  if (type < 0 || static_cast<std::size_t>(type) >= types_.size()) return false;
  robot_types_[robot_id] = type;
  if (auto it = robots_.find(robot_id); it != robots_.end()) it->second.type = type;
  return true;
}

int TrafficManager::robot_type(int robot_id) const {
  return type_of(robot_id);
}

int TrafficManager::type_of(int robot_id) const {
  const auto it = robot_types_.find(robot_id);
  return it == robot_types_.end() ? 0 : it->second;
}

// ---- robots and routes ----------------------------------------------------------------------------

void TrafficManager::install_route(Robot& robot, std::vector<int> points, std::uint64_t version) {
  robot.lost = false;  // a route again: it is heard from
  robot.version = version;
  robot.route = std::move(points);
  const std::size_t n = robot.route.size();
  robot.places.resize(n);
  robot.cum.assign(n, 0.0);
  robot.release_at.assign(n, kInfinity);
  for (std::size_t i = 0; i < n; ++i) robot.places[i] = zones_->place_of(robot.route[i]);
  for (std::size_t i = 1; i < n; ++i)
    robot.cum[i] = robot.cum[i - 1] + search_->edge_length(robot.route[i - 1], robot.route[i]);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    robot.release_at[i] = robot.cum[i] + 0.5 * (robot.cum[i + 1] - robot.cum[i]) + configuration_.release_margin;
  }
  robot.progress = 0.0;
  robot.first_held = 0;
  robot.grant_end = 0;
  robot.wait_since = -1.0;
  robot.frozen = false;
  robot.blocked = false;
  robot.stopped = true;
  robot.blocked_by.clear();
  robot.kept_out_by.clear();
  robot.stopped_for.clear();
  robot.giving_way_to.clear();
  robot.trail_ahead.clear();
  // Previous holdings stay until the robot is past the first edge of the new route.
  std::size_t k = 0;
  while (k + 1 < n && robot.places[k + 1] == robot.places[0]) ++k;
  robot.trail_release = robot.release_at[k];
}

void TrafficManager::change_route(Robot& robot, std::vector<int> points, std::uint64_t version, bool sent) {
  const int start = zones_->place_of(points.front());
  if (!sent) {
    // A route of its own making may start from wherever it has driven to since its last report:
    // all it held stays until it is past the new route's first edge.
    std::vector<int> held = held_places(robot.id);
    held.erase(std::remove(held.begin(), held.end(), start), held.end());
    install_route(robot, std::move(points), version);
    robot.trail = std::move(held);
    return;
  }
  // Sent a route while it waits, it stands where it last reported: its old trail and the places
  // of its old route up to there (and on to the new route's start, when that lies ahead) are
  // where it is. Granted beyond that: places it may still drive into until it drives the new
  // route, held until it reports that it does.
  std::vector<int> ahead = robot.trail_ahead;
  sort_unique(ahead);
  std::vector<int> behind;
  for (int p : robot.trail) {
    if (!std::binary_search(ahead.begin(), ahead.end(), p)) behind.push_back(p);
  }
  int kept = reached_index(robot);
  for (int k = kept; k <= robot.grant_end; ++k) {
    if (robot.places[static_cast<std::size_t>(k)] == start) kept = k;
  }
  // A robot stopped for a body drives on once the body has gone: until the new route reaches it,
  // it may have crept on. Its body's reach further along stays held as well.
  const double crept = robot.cum[static_cast<std::size_t>(kept)] + footprint_reach(robot.type);
  while (kept < robot.grant_end && robot.cum[static_cast<std::size_t>(kept) + 1] <= crept) ++kept;
  for (int k = robot.first_held; k <= kept; ++k) behind.push_back(robot.places[static_cast<std::size_t>(k)]);
  for (int k = kept + 1; k <= robot.grant_end; ++k) ahead.push_back(robot.places[static_cast<std::size_t>(k)]);
  behind.push_back(start);
  sort_unique(behind);
  sort_unique(ahead);
  std::vector<int> only_ahead;
  std::set_difference(ahead.begin(), ahead.end(), behind.begin(), behind.end(), std::back_inserter(only_ahead));
  behind.erase(std::remove(behind.begin(), behind.end(), start), behind.end());
  install_route(robot, std::move(points), version);
  robot.trail.clear();
  std::merge(behind.begin(), behind.end(), only_ahead.begin(), only_ahead.end(), std::back_inserter(robot.trail));
  robot.trail_ahead = std::move(only_ahead);
}

void TrafficManager::wait_for_area(int robot_id, std::vector<int> blockers) {
  blockers.erase(std::remove(blockers.begin(), blockers.end(), robot_id), blockers.end());
  sort_unique(blockers);
  if (blockers.empty()) {
    area_waits_.erase(robot_id);
  } else {
    area_waits_[robot_id] = std::move(blockers);
  }
}

SubmitStatus TrafficManager::submit_route(const RouteRequest& request, double now) {
  (void)now;
  const auto& points = request.points;
  if (points.empty()) return SubmitStatus::kInvalid;
  area_waits_.erase(request.robot_id);
  ways_out_.erase(request.robot_id);
  // Its type's lanes: a route into a lane the vehicle does not fit has an edge missing there.
  const map::RoadGraph& lanes = types_[static_cast<std::size_t>(type_of(request.robot_id))]->lanes;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i] < 0 || static_cast<std::size_t>(points[i]) >= graph_.points.size()) return SubmitStatus::kInvalid;
    if (i == 0) continue;
    const auto& next = lanes.successors[static_cast<std::size_t>(points[i - 1])];
    const bool joined = std::find(next.begin(), next.end(), points[i]) != next.end() ||
                        zones_->place_of(points[i - 1]) == zones_->place_of(points[i]);
    if (!joined) return SubmitStatus::kInvalid;
  }
  auto it = robots_.find(request.robot_id);
  if (it == robots_.end()) {
    entries_.erase(request.robot_id);  // it enters
    Robot robot;
    robot.id = request.robot_id;
    robot.type = type_of(robot.id);
    install_route(robot, points, request.version);
    robots_.emplace(request.robot_id, std::move(robot));
    return SubmitStatus::kAccepted;
  }
  Robot& robot = it->second;
  // A standing robot (frozen, or holding its body) has no route version to be newer than.
  if (!robot.frozen && request.version <= robot.version) return SubmitStatus::kStale;
  const std::vector<int> held = held_places(robot.id);
  if (!std::binary_search(held.begin(), held.end(), zones_->place_of(points.front()))) return SubmitStatus::kInvalid;
  const bool was_standing = robot.frozen;
  change_route(robot, points, request.version, /*sent=*/false);
  robot.pending = Instruction::kNone;
  robot.in_siding = false;
  robot.yield_to.clear();
  // The area of a turn into a place it still holds (it has not driven past the first edge of the
  // route it left by) stays held until it is past this route's first edge: a robot backing out
  // of a place may plan again before it is out. The body it stood with before does not: on the
  // road again, its route's places cover it.
  if (was_standing) {
    pull_back_grants_into(robot);
  } else if (!robot.reach_of_turn) {
    robot.body_reach.clear();
    robot.body_polygon.clear();
  }
  leave_arrival(robot);
  return SubmitStatus::kAccepted;
}

void TrafficManager::report_progress(const ProgressReport& report, double now) {
  (void)now;
  auto it = robots_.find(report.robot_id);
  if (it == robots_.end() || !std::isfinite(report.distance)) return;
  Robot& robot = it->second;
  if (report.version != robot.version) return;
  robot.pending = Instruction::kNone;  // the robot drives this version: the instruction arrived
  if (!robot.trail_ahead.empty()) {
    std::vector<int> kept;
    std::set_difference(robot.trail.begin(), robot.trail.end(), robot.trail_ahead.begin(), robot.trail_ahead.end(),
                        std::back_inserter(kept));
    robot.trail = std::move(kept);
    robot.trail_ahead.clear();
  }
  robot.stopped_for.clear();
  for (int other : report.stopped_for) {
    if (other != robot.id && robots_.count(other) != 0) robot.stopped_for.push_back(other);
  }
  sort_unique(robot.stopped_for);
  const double limit = robot.cum[static_cast<std::size_t>(robot.grant_end)];
  robot.progress = std::clamp(report.distance, robot.progress, std::max(robot.progress, limit));
}

void TrafficManager::pull_back_grants_into(const Robot& standing) {
  // A robot holds where it stands without being granted it (it was standing there when the
  // manager learnt of it, or it came back onto the road it stood at), so another robot may
  // have been granted places in conflict with it. Those grants end before the first such place
  // the other robot has not reached; without this, a follower granted up to a robot standing
  // ahead of it and that robot waited for each other for good.
  for (auto& [id, other] : robots_) {
    if (id == standing.id || other.frozen) continue;
    const int reached = reached_index(other);
    for (int k = reached + 1; k <= other.grant_end; ++k) {
      const int p = other.places[static_cast<std::size_t>(k)];
      if (!closes(standing, p, other.type)) continue;
      int end = k - 1;
      while (end > reached && !zones_->stoppable(other.type, other.places[static_cast<std::size_t>(end)])) --end;
      other.grant_end = end;
      break;
    }
  }
}

void TrafficManager::stand(Robot& robot, const geometry::Polygon& body, const std::vector<int>& under,
                           std::vector<std::vector<int>> touched) {
  int anchor = -1;
  for (std::size_t point = 0; point < graph_.points.size() && anchor < 0; ++point) {
    if (zones_->place_of(static_cast<int>(point)) == under.front()) anchor = static_cast<int>(point);
  }
  // A one-point route at a place under its body, the other places under it as a trail that is
  // never released by progress: it holds where it stands until it sends a route again.
  install_route(robot, {anchor}, robot.version);
  robot.trail.assign(under.begin() + 1, under.end());
  robot.trail_release = kInfinity;
  robot.frozen = true;
  robot.pending = Instruction::kNone;
  robot.in_siding = false;
  robot.body_reach = std::move(touched);
  robot.body_polygon = body;
  robot.reach_of_turn = false;
  robot.arrival_point = -1;  // its body is what it holds now
  robot.arrival_held = false;
  robot.arrival_area.clear();
  robot.arrival_reach.clear();
  pull_back_grants_into(robot);
}

bool TrafficManager::under_body_for(const Robot& robot, int place, int type) const {
  if (robot.body_reach.empty()) return false;
  const auto& reach = robot.body_reach[static_cast<std::size_t>(type)];
  return std::binary_search(reach.begin(), reach.end(), place);
}

bool TrafficManager::closes(const Robot& holder, int place, int type) const {
  if (under_body_for(holder, place, type)) return true;
  if (holder.arrival_held) {
    const auto& reach = holder.arrival_reach[static_cast<std::size_t>(type)];
    if (std::binary_search(reach.begin(), reach.end(), place)) return true;
  }
  const std::vector<int> held = held_places(holder.id);
  return std::any_of(held.begin(), held.end(),
                     [&](int q) { return !under_body(holder, q) && zones_->conflict(holder.type, q, type, place); });
}

bool TrafficManager::freeze_robot(int robot_id, const geometry::Polygon& body, double now) {
  auto it = robots_.find(robot_id);
  if (it == robots_.end()) return false;
  std::vector<std::vector<int>> touched;
  const std::vector<int> under = places_under(body, it->second.type, &touched);
  if (under.empty()) return remove_robot(robot_id, now);
  stand(it->second, body, under, std::move(touched));
  it->second.lost = true;
  return true;
}

bool TrafficManager::hold_body(int robot_id, const geometry::Polygon& body, double now) {
  auto it = robots_.find(robot_id);
  if (it != robots_.end() && !it->second.frozen) return false;
  std::vector<std::vector<int>> touched;
  const std::vector<int> under = places_under(body, type_of(robot_id), &touched);
  if (under.empty()) {
    if (it != robots_.end()) remove_robot(robot_id, now);
    return false;
  }
  if (it == robots_.end()) {
    Robot robot;
    robot.id = robot_id;
    robot.type = type_of(robot_id);
    it = robots_.emplace(robot_id, std::move(robot)).first;
  } else if (held_places(robot_id) == under && it->second.body_reach == touched) {
    it->second.lost = false;  // heard from again, standing where it was lost
    return true;
  }
  stand(it->second, body, under, std::move(touched));
  return true;
}

bool TrafficManager::remove_robot(int robot_id, double now) {
  area_waits_.erase(robot_id);
  ways_out_.erase(robot_id);
  if (robots_.erase(robot_id) == 0) return false;
  for (auto& [id, robot] : robots_) {
    robot.yield_to.erase(std::remove(robot.yield_to.begin(), robot.yield_to.end(), robot_id), robot.yield_to.end());
  }
  removed_.push_back({TrafficEvent::Kind::kRobotRemoved, now, robot_id, {}});
  return true;
}

void TrafficManager::release_passed(Robot& robot) {
  while (robot.first_held < robot.grant_end &&
         robot.progress > robot.release_at[static_cast<std::size_t>(robot.first_held)]) {
    ++robot.first_held;
  }
  if (robot.progress > robot.trail_release) {
    robot.trail.clear();
    robot.trail_ahead.clear();
    robot.body_reach.clear();
    robot.body_polygon.clear();
    robot.reach_of_turn = false;
  }
}

std::vector<int> TrafficManager::robot_ids() const {
  std::vector<int> ids;
  for (const auto& [id, robot] : robots_) ids.push_back(id);
  return ids;
}

std::vector<int> TrafficManager::held_places(int robot_id) const {
  auto it = robots_.find(robot_id);
  if (it == robots_.end()) return {};
  const Robot& robot = it->second;
  std::vector<int> held(robot.trail);
  for (int k = robot.first_held; k <= robot.grant_end; ++k) held.push_back(robot.places[static_cast<std::size_t>(k)]);
  sort_unique(held);
  return held;
}

double TrafficManager::footprint_reach(int type) const {
  double reach = 0.0;
  for (const auto& corner : zones_->vehicle_types()[static_cast<std::size_t>(type)].footprint) {
    reach = std::max(reach, std::hypot(corner.x, corner.y));
  }
  return reach;
}

bool TrafficManager::holds_place_of(int robot_id, int point) const {
  const std::vector<int> held = held_places(robot_id);
  return std::binary_search(held.begin(), held.end(), zones_->place_of(point));
}

const std::vector<int>& TrafficManager::route(int robot_id) const {
  static const std::vector<int> empty;
  auto it = robots_.find(robot_id);
  return it == robots_.end() ? empty : it->second.route;
}

std::uint64_t TrafficManager::version(int robot_id) const {
  auto it = robots_.find(robot_id);
  return it == robots_.end() ? 0 : it->second.version;
}

std::string TrafficManager::check_invariant() const {
  // Conflicts are symmetric: checking each robot's places against the regions of the robots
  // before it finds every conflicting pair in robots x places x conflict-set size x types. A body
  // the robot stands with (body_reach) closes the places it touches; two such bodies may stand
  // close, which no grant made. The tables are by typed(type of the robot checked, place).
  const std::size_t cells = zones_->place_count() * zones_->type_count();
  const int types = static_cast<int>(zones_->type_count());
  std::vector<int> conflicting(cells, -1), held_by(cells, -1), body_of(cells, -1);
  auto report = [](int id, int p, int other) {
    std::ostringstream out;
    out << "robot " << id << " holds place " << p << ", which conflicts with a place robot " << other << " holds";
    return out.str();
  };
  for (const auto& [id, robot] : robots_) {
    const std::vector<int> held = held_places(id);
    for (int p : held) {
      if (under_body(robot, p)) continue;
      const std::size_t at = typed(robot.type, p);
      if (conflicting[at] >= 0) return report(id, p, conflicting[at]);
      if (body_of[at] >= 0) return report(id, p, body_of[at]);
    }
    for (int u = 0; u < types; ++u) {
      int place = -1;
      for_each_reach(robot, u, [&](int p) {
        if (place < 0 && held_by[typed(u, p)] >= 0) place = p;
      });
      if (place >= 0) return report(id, place, held_by[typed(u, place)]);
    }
    for (int p : held) {
      if (under_body(robot, p)) continue;
      held_by[typed(robot.type, p)] = id;
      for (int u = 0; u < types; ++u) {
        for (int q : zones_->conflicts(robot.type, p, u)) conflicting[typed(u, q)] = id;
      }
    }
    for (int u = 0; u < types; ++u) for_each_reach(robot, u, [&](int p) { body_of[typed(u, p)] = id; });
  }
  return {};
}

// ---- the cycle -------------------------------------------------------------------------------------

UpdateResult TrafficManager::update(double now) {
  UpdateResult out;
  out.events.swap(removed_);
  now_ = now;
  slots_.clear();
  for (auto& [id, robot] : robots_) slots_.push_back(&robot);
  for (Robot* robot : slots_) release_passed(*robot);
  rebuild_occupancy();

  std::vector<int> order(slots_.size());
  for (std::size_t s = 0; s < order.size(); ++s) order[s] = static_cast<int>(s);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return higher_priority(*slots_[static_cast<std::size_t>(a)], *slots_[static_cast<std::size_t>(b)]);
  });
  for (int s : order) {
    Robot& robot = *slots_[static_cast<std::size_t>(s)];
    extend(robot, s);
    robot.stopped = stopped_at_grant_end(robot);
    // Stopped short of its grant by another robot's body: it waits for that robot as surely as
    // for one holding the road.
    const bool stopped_by_body = !robot.frozen && !robot.stopped_for.empty();
    if (stopped_by_body) {
      robot.blocked = true;
      robot.blocked_by.insert(robot.blocked_by.end(), robot.stopped_for.begin(), robot.stopped_for.end());
      sort_unique(robot.blocked_by);
    }
    // Standing beside the roads until its work area is clear: it waits for those in it.
    if (const auto area = area_waits_.find(robot.id); robot.frozen && area != area_waits_.end()) {
      for (int id : area->second) {
        if (robots_.count(id) != 0) robot.blocked_by.push_back(id);
      }
      robot.blocked = !robot.blocked_by.empty();
    }
    const bool waiting = robot.blocked && (robot.stopped || stopped_by_body);
    if (!waiting) {
      robot.wait_since = -1.0;
    } else if (robot.wait_since < 0.0) {
      robot.wait_since = now;
    }
  }

  for (Robot* robot : slots_) try_resume(*robot, now, out);
  resolve_cycles(now, out);
  for (int s : order) {
    Robot& robot = *slots_[static_cast<std::size_t>(s)];
    if (robot.wait_since < 0.0 || robot.frozen || now - robot.last_reroute < configuration_.reroute_wait) continue;
    if (robot.in_siding) {
      // Held up on its way to a siding (a robot came to stand on that way): another siding, off
      // the ways of those it yields to and of those that hold it up now.
      if (now - robot.wait_since < configuration_.reroute_wait) continue;
      std::vector<int> others = robot.yield_to;
      others.insert(others.end(), robot.blocked_by.begin(), robot.blocked_by.end());
      sort_unique(others);
      send_to_siding(robot, others, now, out);
      robot.last_reroute = now;
      continue;
    }
    // Behind lost robots, or kept out of a corridor closed behind a transporter (which stands
    // there for minutes), waiting out the whole bound only adds to the wait.
    const auto closes = [&](int id) {
      return std::any_of(pair_closures_.begin(), pair_closures_.end(), [&](const PairClosure& closure) {
        return slots_[static_cast<std::size_t>(closure.transporter)]->id == id;
      });
    };
    const bool behind_lost_only =
        !robot.blocked_by.empty() && std::all_of(robot.blocked_by.begin(), robot.blocked_by.end(), [&](int id) {
          const auto it = robots_.find(id);
          return it != robots_.end() && (it->second.lost || closes(id));
        });
    if (now - robot.wait_since < (behind_lost_only ? configuration_.lost_reroute_wait : configuration_.reroute_wait)) {
      continue;
    }
    // A copy: the new route clears blocked_by, and the event names who it went round.
    const std::vector<int> blockers = robot.blocked_by;
    if (reroute(robot, blockers, now, out, TrafficEvent::Kind::kRerouted)) continue;
    robot.last_reroute = now;
    // No way round a closed lane: its goal lies in it. Waiting at the lane's mouth it may stand
    // where the pair's picker comes by to its stop, and the pair waits for the picker: it waits on
    // a siding off the ways of the transporter and its picker instead.
    std::vector<int> pair;
    for (const PairClosure& closure : pair_closures_) {
      const int transporter = slots_[static_cast<std::size_t>(closure.transporter)]->id;
      if (std::find(blockers.begin(), blockers.end(), transporter) == blockers.end()) continue;
      pair.push_back(transporter);
      if (robots_.count(closure.loader_id) != 0) pair.push_back(closure.loader_id);
    }
    if (pair.size() > 1) send_to_siding(robot, pair, now, out);
  }

  out.grants.reserve(slots_.size());
  for (Robot* robot : slots_) {
    Grant g;
    g.robot_id = robot->id;
    g.version = robot->version;
    g.granted_index = robot->grant_end;
    g.granted_distance = robot->cum[static_cast<std::size_t>(robot->grant_end)];
    const bool at_end = robot->grant_end + 1 == static_cast<int>(robot->route.size());
    if (robot->wait_since >= 0.0) {
      g.status = GrantStatus::kWaiting;
      g.waited_s = now - robot->wait_since;
    } else if (at_end && stopped_at_grant_end(*robot)) {
      g.status = GrantStatus::kArrived;
    } else {
      g.status = GrantStatus::kMoving;
    }
    // An entrant whose claim keeps it out is waited for like a robot on the road.
    g.blocked_by = robot->blocked_by;
    g.blocked_by.insert(g.blocked_by.end(), robot->kept_out_by.begin(), robot->kept_out_by.end());
    sort_unique(g.blocked_by);
    g.instruction = robot->pending;
    if (robot->pending != Instruction::kNone) g.route = robot->route;
    out.grants.push_back(std::move(g));
  }
  return out;
}

}  // namespace fleet::traffic
