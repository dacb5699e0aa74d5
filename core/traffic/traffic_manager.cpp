#include "traffic/traffic_manager.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

namespace fleet::traffic {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Seconds a robot sent a re-route or a siding gets to act on it before a wait cycle may pick it
// again: the robots around it still see it where it stood until it moves.
constexpr double kActOnInstruction = 2.0;

void sort_unique(std::vector<int>& ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

// Direction of travel through `places[index]` inside its corridor: towards the next different
// place on the route, 0 when the route leaves the corridor there or ends. Only robots still to
// drive along a corridor claim its direction; one standing at its goal does not.
int direction_in(const ConflictZones& zones, const std::vector<int>& places, int index) {
  const int p = places[static_cast<std::size_t>(index)];
  if (zones.corridor(p) < 0) return 0;
  const int n = static_cast<int>(places.size());
  int j = index + 1;
  while (j < n && places[static_cast<std::size_t>(j)] == p) ++j;
  if (j < n) return zones.corridor_direction(p, places[static_cast<std::size_t>(j)]);
  return 0;
}

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
  search_ = std::make_unique<RouteSearch>(graph_, *zones_);
  if (configuration.one_way) one_way_ = one_way_plan(graph_, *zones_);
  route_search_ = std::make_unique<RouteSearch>(route_graph(), *zones_);
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
  // Previous holdings stay until the robot is past the first edge of the new route.
  std::size_t k = 0;
  while (k + 1 < n && robot.places[k + 1] == robot.places[0]) ++k;
  robot.trail_release = robot.release_at[k];
}

SubmitStatus TrafficManager::submit_route(const RouteRequest& request, double now) {
  (void)now;
  const auto& points = request.points;
  if (points.empty()) return SubmitStatus::kInvalid;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i] < 0 || static_cast<std::size_t>(points[i]) >= graph_.points.size()) return SubmitStatus::kInvalid;
    if (i == 0) continue;
    const auto& next = graph_.successors[static_cast<std::size_t>(points[i - 1])];
    const bool joined = std::find(next.begin(), next.end(), points[i]) != next.end() ||
                        zones_->place_of(points[i - 1]) == zones_->place_of(points[i]);
    if (!joined) return SubmitStatus::kInvalid;
  }
  auto it = robots_.find(request.robot_id);
  if (it == robots_.end()) {
    entries_.erase(request.robot_id);  // it enters
    Robot robot;
    robot.id = request.robot_id;
    install_route(robot, points, request.version);
    robots_.emplace(request.robot_id, std::move(robot));
    return SubmitStatus::kAccepted;
  }
  Robot& robot = it->second;
  // A standing robot (frozen, or holding its body) has no route version to be newer than.
  if (!robot.frozen && request.version <= robot.version) return SubmitStatus::kStale;
  std::vector<int> held = held_places(robot.id);
  const int start = zones_->place_of(points.front());
  if (!std::binary_search(held.begin(), held.end(), start)) return SubmitStatus::kInvalid;
  held.erase(std::remove(held.begin(), held.end(), start), held.end());
  const bool was_standing = robot.frozen;
  install_route(robot, points, request.version);
  robot.trail = std::move(held);
  robot.pending = Instruction::kNone;
  robot.in_siding = false;
  robot.yield_to.clear();
  if (was_standing) {
    pull_back_grants_into(robot);
  } else {
    robot.body_reach.clear();
  }
  return SubmitStatus::kAccepted;
}

void TrafficManager::report_progress(const ProgressReport& report, double now) {
  (void)now;
  auto it = robots_.find(report.robot_id);
  if (it == robots_.end() || !std::isfinite(report.distance)) return;
  Robot& robot = it->second;
  if (report.version != robot.version) return;
  robot.pending = Instruction::kNone;  // the robot drives this version: the instruction arrived
  robot.stopped_for.clear();
  for (int other : report.stopped_for) {
    if (other != robot.id && robots_.count(other) != 0) robot.stopped_for.push_back(other);
  }
  sort_unique(robot.stopped_for);
  const double limit = robot.cum[static_cast<std::size_t>(robot.grant_end)];
  robot.progress = std::clamp(report.distance, robot.progress, std::max(robot.progress, limit));
}

std::vector<int> TrafficManager::places_under(const geometry::Polygon& body, std::vector<int>* touched) const {
  // Every place whose region the body touches; but when one region holds the whole body (a robot
  // standing on the road), that place alone: whatever touches the body conflicts with it anyway,
  // and the wider set would close the road to a robot standing close behind or ahead.
  std::vector<int> under;
  int holding = -1;
  double holding_distance = kInfinity;
  geometry::Vec2 centre{};
  for (const auto& corner : body) centre = centre + (1.0 / static_cast<double>(body.size())) * corner;
  for (std::size_t p = 0; p < zones_->place_count(); ++p) {
    const auto& region = zones_->region(static_cast<int>(p));
    const bool touches = std::any_of(region.begin(), region.end(), [&](const geometry::Polygon& piece) {
      return geometry::convex_polygons_distance(piece, body) <= 0.0;
    });
    if (!touches) continue;
    under.push_back(static_cast<int>(p));
    if (touched) touched->push_back(static_cast<int>(p));
    const bool holds = std::all_of(body.begin(), body.end(), [&](const geometry::Vec2& corner) {
      return std::any_of(region.begin(), region.end(),
                         [&](const geometry::Polygon& piece) { return geometry::contains(piece, corner); });
    });
    const double d = geometry::distance(zones_->position(static_cast<int>(p)), centre);
    if (holds && d < holding_distance) {
      holding = static_cast<int>(p);
      holding_distance = d;
    }
  }
  if (holding >= 0) return {holding};
  return under;
}

void TrafficManager::pull_back_grants_into(const Robot& standing) {
  // A robot holds where it stands without being granted it (it was standing there when the
  // manager learnt of it, or it came back onto the road it stood at), so another robot may
  // have been granted places in conflict with it. Those grants end before the first such place
  // the other robot has not reached; without this, a follower granted up to a robot standing
  // ahead of it and that robot waited for each other for good.
  for (auto& [id, other] : robots_) {
    if (id == standing.id || other.frozen) continue;
    // The places it stands in: up to the one it is driving into.
    int reached = other.first_held;
    while (reached < other.grant_end && other.cum[static_cast<std::size_t>(reached)] + 1e-6 < other.progress) ++reached;
    for (int k = reached + 1; k <= other.grant_end; ++k) {
      const int p = other.places[static_cast<std::size_t>(k)];
      if (!closes(standing, p)) continue;
      int end = k - 1;
      while (end > reached && !zones_->stoppable(other.places[static_cast<std::size_t>(end)])) --end;
      other.grant_end = end;
      break;
    }
  }
}

void TrafficManager::stand(Robot& robot, const std::vector<int>& under, std::vector<int> touched) {
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
  pull_back_grants_into(robot);
}

bool TrafficManager::under_body(const Robot& robot, int place) const {
  return std::binary_search(robot.body_reach.begin(), robot.body_reach.end(), place);
}

bool TrafficManager::closes(const Robot& holder, int place) const {
  if (under_body(holder, place)) return true;
  const std::vector<int> held = held_places(holder.id);
  return std::any_of(held.begin(), held.end(),
                     [&](int q) { return !under_body(holder, q) && zones_->conflict(place, q); });
}

bool TrafficManager::freeze_robot(int robot_id, const geometry::Polygon& body, double now) {
  auto it = robots_.find(robot_id);
  if (it == robots_.end()) return false;
  std::vector<int> touched;
  const std::vector<int> under = places_under(body, &touched);
  if (under.empty()) return remove_robot(robot_id, now);
  stand(it->second, under, std::move(touched));
  it->second.lost = true;
  return true;
}

bool TrafficManager::hold_body(int robot_id, const geometry::Polygon& body, double now) {
  auto it = robots_.find(robot_id);
  if (it != robots_.end() && !it->second.frozen) return false;
  std::vector<int> touched;
  const std::vector<int> under = places_under(body, &touched);
  if (under.empty()) {
    if (it != robots_.end()) remove_robot(robot_id, now);
    return false;
  }
  if (it == robots_.end()) {
    Robot robot;
    robot.id = robot_id;
    it = robots_.emplace(robot_id, std::move(robot)).first;
  } else if (held_places(robot_id) == under && it->second.body_reach == touched) {
    it->second.lost = false;  // heard from again, standing where it was lost
    return true;
  }
  stand(it->second, under, std::move(touched));
  return true;
}

bool TrafficManager::remove_robot(int robot_id, double now) {
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
    robot.body_reach.clear();
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

void TrafficManager::claim_entry(int robot_id, int point, double now) {
  if (point < 0 || static_cast<std::size_t>(point) >= graph_.points.size()) return;
  const int place = zones_->place_of(point);
  auto it = entries_.find(robot_id);
  if (it == entries_.end() || it->second.place != place) {
    entries_[robot_id] = {place, now};
    return;
  }
  EntryClaim& claim = it->second;
  if (claim_active(robot_id, claim, now) && claim_waits_on_itself(robot_id, claim)) {
    claim.lifted_until = now + configuration_.priority_wait;
  }
}

bool TrafficManager::claim_in_line(int robot_id, const EntryClaim& claim, double now) const {
  // A robot the manager knows (standing at a loading area) is already on the roads' edge: it
  // claims no place in line.
  return robots_.count(robot_id) == 0 && now - claim.since >= configuration_.priority_wait;
}

bool TrafficManager::claim_active(int robot_id, const EntryClaim& claim, double now) const {
  return claim_in_line(robot_id, claim, now) && now >= claim.lifted_until;
}

bool TrafficManager::claim_waits_on_itself(int robot_id, const EntryClaim& claim) const {
  // Depth-first over who waits for whom: a robot on the roads waits for the robots it is blocked
  // by and the entrants whose claims keep it out; an entrant waits for the holders of its entry.
  std::vector<int> stack = holders_of(claim.place, robot_id);
  std::vector<int> seen;
  while (!stack.empty()) {
    const int id = stack.back();
    stack.pop_back();
    if (id == robot_id) return true;
    if (std::find(seen.begin(), seen.end(), id) != seen.end()) continue;
    seen.push_back(id);
    if (auto robot = robots_.find(id); robot != robots_.end()) {
      stack.insert(stack.end(), robot->second.blocked_by.begin(), robot->second.blocked_by.end());
      stack.insert(stack.end(), robot->second.kept_out_by.begin(), robot->second.kept_out_by.end());
    } else if (auto entrant = entries_.find(id); entrant != entries_.end()) {
      const std::vector<int> holders = holders_of(entrant->second.place, id);
      stack.insert(stack.end(), holders.begin(), holders.end());
    }
  }
  return false;
}

void TrafficManager::drop_entry(int robot_id) {
  entries_.erase(robot_id);
}

std::vector<int> TrafficManager::earlier_entry_claims(int point, int robot_id, double now) const {
  std::vector<int> out;
  if (point < 0 || static_cast<std::size_t>(point) >= graph_.points.size()) return out;
  const int place = zones_->place_of(point);
  const auto mine = entries_.find(robot_id);
  const auto self = robots_.find(robot_id);
  for (const auto& [id, claim] : entries_) {
    if (id == robot_id || !claim_in_line(id, claim, now)) continue;
    if (mine != entries_.end() &&
        (mine->second.since < claim.since || (mine->second.since == claim.since && robot_id < id))) {
      continue;
    }
    if (!zones_->conflict(place, claim.place)) continue;
    if (self != robots_.end() && closes(self->second, claim.place)) continue;
    out.push_back(id);
  }
  return out;
}

std::vector<int> TrafficManager::holders_in_conflict(int point, int robot_id) const {
  if (point < 0 || static_cast<std::size_t>(point) >= graph_.points.size()) return {};
  return holders_of(zones_->place_of(point), robot_id);
}

std::vector<int> TrafficManager::holders_of(int place, int robot_id) const {
  std::vector<int> out;
  for (const auto& [id, robot] : robots_) {
    if (id != robot_id && closes(robot, place)) out.push_back(id);
  }
  return out;
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
  // before it finds every conflicting pair in robots x places x conflict-set size. A body the
  // robot stands with (body_reach) closes the places it touches; two such bodies may stand
  // close, which no grant made.
  std::vector<int> conflicting(zones_->place_count(), -1), held_by(zones_->place_count(), -1),
      body_of(zones_->place_count(), -1);
  auto report = [](int id, int p, int other) {
    std::ostringstream out;
    out << "robot " << id << " holds place " << p << ", which conflicts with a place robot " << other << " holds";
    return out.str();
  };
  for (const auto& [id, robot] : robots_) {
    const std::vector<int> held = held_places(id);
    for (int p : held) {
      if (under_body(robot, p)) continue;
      const auto sp = static_cast<std::size_t>(p);
      if (conflicting[sp] >= 0) return report(id, p, conflicting[sp]);
      if (body_of[sp] >= 0) return report(id, p, body_of[sp]);
    }
    for (int p : robot.body_reach) {
      if (held_by[static_cast<std::size_t>(p)] >= 0) return report(id, p, held_by[static_cast<std::size_t>(p)]);
    }
    for (int p : held) {
      if (under_body(robot, p)) continue;
      held_by[static_cast<std::size_t>(p)] = id;
      for (int q : zones_->conflicts(p)) conflicting[static_cast<std::size_t>(q)] = id;
    }
    for (int p : robot.body_reach) body_of[static_cast<std::size_t>(p)] = id;
  }
  return {};
}

// ---- occupancy --------------------------------------------------------------------------------------

int TrafficManager::direction_at(const Robot& robot, int index) const {
  return direction_in(*zones_, robot.places, index);
}

int TrafficManager::next_stretch_end(const Robot& robot) const {
  const int last = static_cast<int>(robot.route.size()) - 1;
  int j = robot.grant_end;
  if (j >= last) return last;
  ++j;
  while (j < last && !zones_->stoppable(robot.places[static_cast<std::size_t>(j)])) ++j;
  return j;
}

void TrafficManager::mark(const Robot& robot, int slot, int index) {
  const std::uint64_t bit = std::uint64_t{1} << (slot % 64);
  const std::size_t word = static_cast<std::size_t>(slot / 64);
  const int p = robot.places[static_cast<std::size_t>(index)];
  if (under_body(robot, p)) {
    occupancy_[static_cast<std::size_t>(p) * words_ + word] |= bit;
  } else {
    for (int q : zones_->conflicts(p)) occupancy_[static_cast<std::size_t>(q) * words_ + word] |= bit;
  }
  const int d = direction_at(robot, index);
  const int c = zones_->corridor(p);
  if (d != 0) {
    add_span(c, slot, d, zones_->corridor_index(p), false);
  } else if (c >= 0 && index + 1 == static_cast<int>(robot.route.size()) && !robot.in_siding) {
    // Standing at the end of its route, it leaves the way the corridor lets it: either way in a
    // two-way corridor, so nobody drives up to it head-on; only on along a one-way corridor, so
    // robots behind it queue up to it instead of waiting outside while it works at a loading area.
    // (A robot in a siding stands off the others' routes and leaves only once they have passed.)
    const int leaves = configuration_.one_way ? one_way_.corridor_direction[static_cast<std::size_t>(c)] : 0;
    add_span(c, slot, leaves, zones_->corridor_index(p), false);
  }
}

void TrafficManager::add_span(int corridor, int slot, int direction, int index, bool reserved) {
  auto& spans = spans_[static_cast<std::size_t>(corridor)];
  for (auto& span : spans) {
    if (span.slot == slot && span.direction == direction && span.reserved == reserved) {
      span.lo = std::min(span.lo, index);
      span.hi = std::max(span.hi, index);
      return;
    }
  }
  spans.push_back({slot, direction, index, index, reserved});
}

void TrafficManager::rebuild_occupancy() {
  words_ = std::max<std::size_t>(1, (slots_.size() + 63) / 64);
  occupancy_.assign(zones_->place_count() * words_, 0);
  spans_.resize(zones_->corridor_count());
  for (auto& spans : spans_) spans.clear();
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    const Robot& robot = *slots_[s];
    const std::uint64_t bit = std::uint64_t{1} << (s % 64);
    for (int k = robot.first_held; k <= robot.grant_end; ++k) mark(robot, static_cast<int>(s), k);
    for (int p : robot.trail) {
      if (under_body(robot, p)) continue;
      for (int q : zones_->conflicts(p)) occupancy_[static_cast<std::size_t>(q) * words_ + s / 64] |= bit;
    }
    for (int p : robot.body_reach) occupancy_[static_cast<std::size_t>(p) * words_ + s / 64] |= bit;
  }
  // Entry claims of robots waiting beside the roads longer than priority_wait.
  entry_closed_.assign(zones_->place_count(), 0);
  for (const auto& [id, claim] : entries_) {
    if (!claim_active(id, claim, now_)) continue;
    for (int q : zones_->conflicts(claim.place)) entry_closed_[static_cast<std::size_t>(q)] = 1;
  }
  // Reservations of robots waiting longer than priority_wait: the places of the stretch they wait
  // for, and its corridor direction, against robots that would newly enter them.
  claim_place_.assign(zones_->place_count(), -1);
  std::vector<int> claimants;
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    const Robot& robot = *slots_[s];
    if (robot.wait_since >= 0.0 && robot.blocked && now_ - robot.wait_since >= configuration_.priority_wait) {
      claimants.push_back(static_cast<int>(s));
    }
  }
  std::sort(claimants.begin(), claimants.end(), [&](int a, int b) {
    return higher_priority(*slots_[static_cast<std::size_t>(a)], *slots_[static_cast<std::size_t>(b)]);
  });
  for (int s : claimants) {
    const Robot& robot = *slots_[static_cast<std::size_t>(s)];
    const int end = next_stretch_end(robot);
    for (int j = robot.grant_end + 1; j <= end; ++j) {
      const int p = robot.places[static_cast<std::size_t>(j)];
      for (int q : zones_->conflicts(p)) {
        if (claim_place_[static_cast<std::size_t>(q)] < 0) claim_place_[static_cast<std::size_t>(q)] = s;
      }
      const int d = direction_at(robot, j);
      if (d != 0) add_span(zones_->corridor(p), s, d, zones_->corridor_index(p), true);
    }
  }
}

bool TrafficManager::entry_closes(const std::vector<int>& places, int index) const {
  // Closed to robots coming from outside the claim's places; one inside may drive on and out.
  const auto closed = [&](int k) {
    return entry_closed_[static_cast<std::size_t>(places[static_cast<std::size_t>(k)])] != 0;
  };
  return closed(index) && (index == 0 || !closed(index - 1));
}

bool TrafficManager::higher_priority(const Robot& a, const Robot& b) const {
  const double wa = a.wait_since >= 0.0 ? a.wait_since : kInfinity;
  const double wb = b.wait_since >= 0.0 ? b.wait_since : kInfinity;
  if (wa != wb) return wa < wb;
  return a.id < b.id;
}

// Robots that keep robot `slot` out of `places[index]`: holders of conflicting places, robots in
// the same corridor driving the other way, and reservations of older waiting robots.
bool TrafficManager::place_free_for(int slot, const std::vector<int>& places, int index,
                                    std::vector<int>& blockers) const {
  const std::size_t before = blockers.size();
  const int p = places[static_cast<std::size_t>(index)];
  const auto own_word = static_cast<std::size_t>(slot / 64);
  const std::uint64_t own_bit = std::uint64_t{1} << (slot % 64);
  auto collect = [&](const std::uint64_t* words) {
    for (std::size_t w = 0; w < words_; ++w) {
      std::uint64_t bits = words[w];
      if (w == own_word) bits &= ~own_bit;
      while (bits != 0) {
        const int b = __builtin_ctzll(bits);
        bits &= bits - 1;
        blockers.push_back(static_cast<int>(w * 64) + b);
      }
    }
  };
  collect(&occupancy_[static_cast<std::size_t>(p) * words_]);
  auto claimed_by = [&](int w) {
    if (w < 0 || w == slot) return;
    const Robot& claimant = *slots_[static_cast<std::size_t>(w)];
    const Robot& self = *slots_[static_cast<std::size_t>(slot)];
    // The robots a claimant waits for must stay free to move out of its way.
    if (std::find(claimant.blocked_by.begin(), claimant.blocked_by.end(), self.id) != claimant.blocked_by.end()) return;
    if (higher_priority(self, claimant)) return;
    blockers.push_back(w);
  };
  // The claimant of an entry is off the graph: it blocks without being a robot to wait for
  // (extend notes it in kept_out_by).
  if (entry_closes(places, index)) return false;
  // A reserved place is closed to robots coming from outside the reservation; one inside may leave.
  const int claimant = claim_place_[static_cast<std::size_t>(p)];
  if (claimant >= 0 &&
      (index == 0 || claim_place_[static_cast<std::size_t>(places[static_cast<std::size_t>(index - 1)])] != claimant)) {
    claimed_by(claimant);
  }
  // Head-on: someone in this corridor driving the other way, ahead of this place (robots driving
  // apart do not meet). Around a loop corridor everyone is ahead.
  const int d = direction_in(*zones_, places, index);
  if (d != 0) {
    const int c = zones_->corridor(p);
    const int at = zones_->corridor_index(p);
    const bool loop = zones_->corridor_is_loop(c);
    int before_index = index - 1;
    while (before_index >= 0 && places[static_cast<std::size_t>(before_index)] == p) --before_index;
    // Only a robot entering the corridor respects reservations: one inside must be free to leave.
    const bool entering = before_index < 0 || zones_->corridor(places[static_cast<std::size_t>(before_index)]) != c;
    for (const CorridorSpan& span : spans_[static_cast<std::size_t>(c)]) {
      if (span.slot == slot || (span.direction != -d && span.direction != 0)) continue;
      const bool ahead = loop || (d > 0 ? span.hi >= at : span.lo <= at);
      if (!ahead) continue;
      if (span.reserved) {
        if (entering) claimed_by(span.slot);
      } else {
        blockers.push_back(span.slot);
      }
    }
  }
  return blockers.size() == before;
}

void TrafficManager::extend(Robot& robot, int slot) {
  const int last = static_cast<int>(robot.route.size()) - 1;
  robot.blocked = false;
  robot.blocked_by.clear();
  robot.kept_out_by.clear();
  if (robot.frozen) return;
  const double target = robot.progress + configuration_.lookahead;
  std::vector<int> blockers;
  while (robot.grant_end < last && robot.cum[static_cast<std::size_t>(robot.grant_end)] < target) {
    int j = robot.grant_end + 1;
    bool free = true;
    for (;; ++j) {
      if (!place_free_for(slot, robot.places, j, blockers)) {
        free = false;
        break;
      }
      if (j == last || zones_->stoppable(robot.places[static_cast<std::size_t>(j)])) break;
    }
    if (!free) {
      robot.blocked = true;
      sort_unique(blockers);
      for (int b : blockers) robot.blocked_by.push_back(slots_[static_cast<std::size_t>(b)]->id);
      std::sort(robot.blocked_by.begin(), robot.blocked_by.end());
      if (entry_closes(robot.places, j)) {
        const int p = robot.places[static_cast<std::size_t>(j)];
        for (const auto& [id, claim] : entries_) {
          if (claim_active(id, claim, now_) && zones_->conflict(p, claim.place)) robot.kept_out_by.push_back(id);
        }
      }
      break;
    }
    for (int k = robot.grant_end + 1; k <= j; ++k) mark(robot, slot, k);
    robot.grant_end = j;
  }
}

bool TrafficManager::stopped_at_grant_end(const Robot& robot) const {
  return robot.progress >= robot.cum[static_cast<std::size_t>(robot.grant_end)] - configuration_.stop_tolerance;
}

int TrafficManager::anchor_index(const Robot& robot) const {
  if (stopped_at_grant_end(robot)) return robot.grant_end;
  int k = robot.grant_end;
  const double behind = robot.progress + configuration_.stop_tolerance;
  while (k > robot.first_held && robot.cum[static_cast<std::size_t>(k)] > behind) --k;
  return k;
}

// ---- re-routes and sidings -------------------------------------------------------------------------

std::vector<std::uint8_t> TrafficManager::places_of_others(const std::vector<int>& others, bool with_next_stretch,
                                                           double window) const {
  std::vector<std::uint8_t> mask(zones_->place_count(), 0);
  auto add = [&](int p) {
    for (int q : zones_->conflicts(p)) mask[static_cast<std::size_t>(q)] = 1;
  };
  for (int id : others) {
    auto it = robots_.find(id);
    if (it == robots_.end()) continue;
    const Robot& o = it->second;
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

bool TrafficManager::first_stretch_free(const std::vector<int>& points, int slot) const {
  std::vector<int> places(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) places[i] = zones_->place_of(points[i]);
  const int last = static_cast<int>(places.size()) - 1;
  std::vector<int> blockers;
  for (int j = 1; j <= last; ++j) {
    if (!place_free_for(slot, places, j, blockers)) return false;
    if (zones_->stoppable(places[static_cast<std::size_t>(j)])) break;
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
  std::vector<int> held = held_places(robot.id);
  const int start = zones_->place_of(points.front());
  held.erase(std::remove(held.begin(), held.end(), start), held.end());
  install_route(robot, std::move(points), robot.version + 1);
  robot.trail = std::move(held);
  robot.pending = instruction;
  robot.last_reroute = now;
}

bool TrafficManager::reroute(Robot& robot, const std::vector<int>& others, double now, UpdateResult& out,
                             TrafficEvent::Kind kind, bool against_one_way) {
  const int slot = slot_of(robot.id);
  const int from = anchor_index(robot);
  const int anchor = robot.route[static_cast<std::size_t>(from)];
  const int goal = robot.route.back();
  const auto blocked = places_of_others(others, true, 0.0);
  std::vector<int> path = (against_one_way ? search_ : route_search_)->shortest(anchor, goal, &blocked);
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
      for (int q : zones_->conflicts(p)) here[static_cast<std::size_t>(q)] = 1;
    }
  }
  // The robot may drive through nothing another robot holds ...
  std::vector<int> everyone;
  for (const auto& [id, o] : robots_) {
    if (id != robot.id) everyone.push_back(id);
  }
  const auto through = places_of_others(everyone, false, 0.0);
  // ... and must end off the others' remaining routes, or it would stand in their way again; when
  // no such place is reachable, off their next `siding_window` metres (they pass it before it
  // matters).
  std::vector<int> path;
  for (double window : {kInfinity, configuration_.siding_window}) {
    auto avoid = places_of_others(others, true, window);
    for (std::size_t p = 0; p < avoid.size(); ++p) {
      avoid[p] = static_cast<std::uint8_t>(avoid[p] | through[p] | here[p]);
    }
    path = search_->nearest(
        anchor, [&](int place) { return zones_->stoppable(place) && avoid[static_cast<std::size_t>(place)] == 0; },
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
  std::vector<int> path = route_search_->shortest(robot.route.back(), robot.resume_goal, nullptr);
  if (path.empty()) path = search_->shortest(robot.route.back(), robot.resume_goal, nullptr);
  if (path.size() < 2) {
    // At the goal already, or the goal is unreachable: nothing to resume.
    if (path.size() == 1) robot.in_siding = false;
    return;
  }
  std::vector<int> alive;
  for (int id : robot.yield_to) {
    if (robots_.count(id) != 0) alive.push_back(id);
  }
  const auto theirs = places_of_others(alive, true, configuration_.siding_window);
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
    bool resolved = false;
    for (int s : component) {
      Robot& victim = *slots_[static_cast<std::size_t>(s)];
      if (now - victim.last_reroute < kActOnInstruction) continue;
      // A member already yielding to it on a siding makes way for it: sending it off as well
      // would only swap who yields, again and again.
      const bool yielded_to = std::any_of(ids.begin(), ids.end(), [&](int id) {
        const Robot& other = robots_.at(id);
        return other.in_siding &&
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
        resolved = true;
        break;
      }
    }
    // Last resort: a way round against a one-way corridor. Robots standing where the one-way
    // plan does not expect them (a map switch changed the corridors' directions) can face each
    // other with no way out along the plan; driving against it is safe, as nobody enters a
    // corridor towards a robot driving in it (place_free_for).
    for (std::size_t k = 0; !resolved && configuration_.one_way && k < component.size(); ++k) {
      Robot& victim = *slots_[static_cast<std::size_t>(component[k])];
      resolved = reroute(victim, blockers_of(victim), now, out, TrafficEvent::Kind::kDeadlockResolved, true);
    }
    if (!resolved) out.events.push_back({TrafficEvent::Kind::kUnresolvedDeadlock, now, ids.front(), ids});
  }
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
    if (robot.wait_since < 0.0 || robot.in_siding || now - robot.last_reroute < configuration_.reroute_wait) continue;
    const bool behind_lost_only =
        !robot.blocked_by.empty() && std::all_of(robot.blocked_by.begin(), robot.blocked_by.end(), [&](int id) {
          const auto it = robots_.find(id);
          return it != robots_.end() && it->second.lost;
        });
    if (now - robot.wait_since < (behind_lost_only ? configuration_.lost_reroute_wait : configuration_.reroute_wait)) {
      continue;
    }
    if (!reroute(robot, robot.blocked_by, now, out, TrafficEvent::Kind::kRerouted)) robot.last_reroute = now;
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
    g.blocked_by = robot->blocked_by;
    g.instruction = robot->pending;
    if (robot->pending != Instruction::kNone) g.route = robot->route;
    out.grants.push_back(std::move(g));
  }
  return out;
}

}  // namespace fleet::traffic
