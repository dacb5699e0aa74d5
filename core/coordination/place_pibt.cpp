#include "coordination/place_pibt.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace fleet::coordination {

PlacePibt::PlacePibt(PlaceGraph& graph, std::uint64_t seed)
    : graph_(graph),
      rng_(seed),
      standing_(static_cast<std::size_t>(graph.place_count()), -1),
      planned_at_(static_cast<std::size_t>(graph.place_count()), -1),
      search_depth_(static_cast<std::size_t>(graph.place_count()), kFar),
      search_first_(static_cast<std::size_t>(graph.place_count()), -1) {
  for (const auto& type : graph.zones().params().vehicle_types) backs_up_.push_back(type.backs_up ? 1 : 0);
}

bool PlacePibt::backs_up(int type) const {
  const auto t = static_cast<std::size_t>(type);
  return t >= backs_up_.size() || backs_up_[t] != 0;
}

const std::vector<int>& PlacePibt::moves_back(int type, int place) const {
  static const std::vector<int> kNone;
  return backs_up(type) ? graph_.predecessors(type, place) : kNone;
}

void PlacePibt::reached_goal(int robot) {
  if (robot < static_cast<int>(priority_.size())) {
    priority_[static_cast<std::size_t>(robot)] = std::uniform_real_distribution<double>(0.0, 1.0)(rng_);
  }
}

double PlacePibt::candidate_cost(int robot, int place) const {
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  return r.goal < 0 ? 0.0 : graph_.distance(r.type, place, r.goal);
}

PlacePibt::Check PlacePibt::check(int robot, int place, std::vector<int>& blockers) const {
  blockers.clear();
  const auto& zones = graph_.zones();
  const int type = robots_[static_cast<std::size_t>(robot)].type;
  const int from = robots_[static_cast<std::size_t>(robot)].place;
  if (closed_ != nullptr && place != from && closed_->closer(type, place, robot, from) != kOpen) return Check::kTaken;
  for (int other_type = 0; other_type < graph_.type_count(); ++other_type) {
    for (const int q : zones.conflicts(type, place, other_type)) {
      const int planned = planned_at_[static_cast<std::size_t>(q)];
      if (planned >= 0 && planned != robot && robots_[static_cast<std::size_t>(planned)].type == other_type) {
        return Check::kTaken;
      }
      const int standing = standing_[static_cast<std::size_t>(q)];
      if (standing < 0 || standing == robot || robots_[static_cast<std::size_t>(standing)].type != other_type) continue;
      const auto s = static_cast<std::size_t>(standing);
      if (pushing_[s]) return Check::kTaken;  // it waits for a chain that leads here: a cycle
      if (planned_[s] >= 0) {
        if (planned_[s] == robots_[s].place) return Check::kTaken;  // it stays
        continue;                                                   // it moves on: follow it
      }
      if (std::find(blockers.begin(), blockers.end(), standing) == blockers.end()) blockers.push_back(standing);
    }
  }
  return blockers.empty() ? Check::kFree : Check::kBlocked;
}

template <typename Clear>
PlacePibt::WayOut PlacePibt::search_way(int robot, int from, int other, int reach, bool around_standing,
                                        const Clear& clear) {
  // Breadth-first over the robot's moves either way (forward or backing up), never through the
  // other's body nor where a planned robot (or, around_standing, any other robot standing) rules
  // out, to the nearest place `clear` accepts; bounded to `reach` moves.
  const auto& zones = graph_.zones();
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  const PlaceRobot& o = robots_[static_cast<std::size_t>(other)];
  std::vector<int> blockers;
  WayOut found;
  search_depth_[static_cast<std::size_t>(from)] = 0;
  search_first_[static_cast<std::size_t>(from)] = -1;
  search_touched_.push_back(from);
  for (std::size_t next = 0; next < search_touched_.size(); ++next) {
    const int at = search_touched_[next];
    const int depth = search_depth_[static_cast<std::size_t>(at)];
    if (clear(at)) {
      found = {depth, search_first_[static_cast<std::size_t>(at)]};
      break;
    }
    if (depth >= reach) continue;
    for (const auto* moves : {&graph_.successors(r.type, at), &moves_back(r.type, at)}) {
      for (const int place : *moves) {
        auto& d = search_depth_[static_cast<std::size_t>(place)];
        if (d != kFar || (o.place >= 0 && zones.conflict(r.type, place, o.type, o.place))) continue;
        const Check c = check(robot, place, blockers);
        if (c == Check::kTaken) continue;
        if (around_standing && c == Check::kBlocked &&
            std::any_of(blockers.begin(), blockers.end(), [&](int b) { return b != other; })) {
          continue;
        }
        d = depth + 1;
        search_first_[static_cast<std::size_t>(place)] =
            at == from ? place : search_first_[static_cast<std::size_t>(at)];
        search_touched_.push_back(place);
      }
    }
  }
  for (const int place : search_touched_) search_depth_[static_cast<std::size_t>(place)] = kFar;
  search_touched_.clear();
  return found;
}

bool PlacePibt::in_way_of(int type, int place, int pusher, int wanted) const {
  const PlaceRobot& p = robots_[static_cast<std::size_t>(pusher)];
  if (wanted >= 0 && graph_.zones().conflict(type, place, p.type, wanted)) return true;
  if (p.place >= 0 || closed_ == nullptr) return false;
  const int area = closed_->by_area[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)];
  return area == pusher || area == kClosedByMany;
}

int PlacePibt::moves_out(int robot, int from, int pusher, int wanted) {
  // Bounded to the reach of a body or two.
  constexpr int kReach = 16;
  const int type = robots_[static_cast<std::size_t>(robot)].type;
  return search_way(robot, from, pusher, kReach, false,
                    [&](int place) { return !in_way_of(type, place, pusher, wanted); })
      .moves;
}

void PlacePibt::take(int robot, int place) {
  planned_[static_cast<std::size_t>(robot)] = place;
  planned_at_[static_cast<std::size_t>(place)] = robot;
}

void PlacePibt::plan_robot(int robot, int pusher, int wanted) {
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  const bool pushed = pusher >= 0;
  struct Candidate {
    int place;
    int stays_in_the_way;  ///< pushed: 1 when the place still conflicts with the one the pusher wants
    double cost;
    int blocked;
    unsigned tie;
  };
  if (!pushed && give_way(robot)) return;
  std::vector<Candidate> candidates;
  std::vector<int> blockers;
  // A body spans several places, so one move may not clear the way: a pushed robot takes a move
  // that clears it, or else one on a shortest way out of it, the pusher pushing again each step.
  const int way_out = pushed ? moves_out(robot, r.place, pusher, wanted) : 0;
  auto add = [&](int place) {
    const Check c = check(robot, place, blockers);
    if (c == Check::kTaken) return;
    if (!pushed && place != r.place && meets_head_on(robot, place)) {
      // It waits outside rather than turn away from its way.
      candidates.push_back({r.place, 0, candidate_cost(robot, place), 0, 0U});
      return;
    }
    int in_the_way = 0;
    if (pushed && in_way_of(r.type, place, pusher, wanted)) {
      if (way_out >= kFar || moves_out(robot, place, pusher, wanted) >= way_out) return;
      in_the_way = 1;
    }
    // Equally near, the route's own next place first: the robot drives on without a new route.
    const auto drawn = static_cast<unsigned>(rng_());
    const unsigned tie = place == r.preferred ? 0U : drawn;
    candidates.push_back({place, in_the_way, candidate_cost(robot, place), c == Check::kBlocked ? 1 : 0, tie});
  };
  if (!pushed) add(r.place);
  for (const int next : graph_.successors(r.type, r.place)) add(next);
  const auto self = static_cast<std::size_t>(robot);
  if (!pushed && r.goal >= 0 && standing_plans_[self] >= kStandingBeforeBackingUp) {
    // Robots that box one another in where each has one way on stand for ever unless one backs
    // up: a robot that has stood this long backs up along its lane where that is free at once,
    // rather than stand.
    const auto& forward = graph_.successors(r.type, r.place);
    for (const int back : moves_back(r.type, r.place)) {
      if (std::find(forward.begin(), forward.end(), back) == forward.end() &&
          check(robot, back, blockers) == Check::kFree) {
        add(back);
      }
    }
    for (Candidate& candidate : candidates) {
      if (candidate.place == r.place) candidate.stays_in_the_way = 1;
    }
  }
  if (pushed) {
    // Backing up along its lane makes room where the lanes run one way only.
    const auto& forward = graph_.successors(r.type, r.place);
    for (const int back : moves_back(r.type, r.place)) {
      if (std::find(forward.begin(), forward.end(), back) == forward.end()) add(back);
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.stays_in_the_way != b.stays_in_the_way) return a.stays_in_the_way < b.stays_in_the_way;
    if (a.cost != b.cost) return a.cost < b.cost;
    if (a.blocked != b.blocked) return a.blocked < b.blocked;
    return a.tie < b.tie;
  });
  for (const Candidate& candidate : candidates) {
    if (candidate.place == r.place) {
      take(robot, r.place);
      return;
    }
    if (check(robot, candidate.place, blockers) == Check::kTaken) continue;
    push_out_of_the_way(robot, candidate.place, blockers);
    if (check(robot, candidate.place, blockers) == Check::kFree) {
      take(robot, candidate.place);
      return;
    }
  }
  // No move is free: the robot stays. Standing is always free (no robot plans into a place
  // conflicting with where an unplanned or in-progress robot stands), so a pusher that cannot
  // get its place tries its next candidate and at worst stays too.
  take(robot, r.place);
}

void PlacePibt::push_out_of_the_way(int robot, int place, const std::vector<int>& standing) {
  // Every robot standing in the way is asked to move out of it (or at least away from it), the
  // pusher in progress meanwhile so that none of them plans into its place.
  const auto self = static_cast<std::size_t>(robot);
  pushing_[self] = 1;
  for (const int other : standing) {
    if (planned_[static_cast<std::size_t>(other)] < 0) plan_robot(other, robot, place);
  }
  pushing_[self] = 0;
}

int PlacePibt::best_move(int robot) const {
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  if (r.goal < 0) return -1;
  int best = -1;
  double best_cost = candidate_cost(robot, r.place);
  for (const int next : graph_.successors(r.type, r.place)) {
    if (const double cost = candidate_cost(robot, next); cost < best_cost) {
      best = next;
      best_cost = cost;
    }
  }
  return best;
}

bool PlacePibt::give_way(int robot) {
  // The robot's way on is blocked by one that wants to pass where it stands and cannot get out of
  // its way (a dead end, or robots boxed in behind it): pushing it back is futile, the two must
  // swap, and only the robot outside can make room. It backs off along a shortest way to a place
  // clear of the other's next places, the other following it, until it can step aside and let it
  // pass [Okumura 2023, section 5, the swap].
  const auto self = static_cast<std::size_t>(robot);
  const PlaceRobot& r = robots_[self];
  const int giving_way_to = giving_way_to_[self];
  giving_way_to_[self] = -1;
  const int wanted = best_move(robot);
  if (wanted < 0) return false;
  const auto& zones = graph_.zones();
  if (giving_way_to >= 0) {
    // Once backing off for it, the robot keeps off the other's way until it has passed.
    const PlaceRobot& o = robots_[static_cast<std::size_t>(giving_way_to)];
    const std::vector<int> its_way = path_ahead(giving_way_to, o.place);
    // A robot that does not take the room it is given (it waits in turn) ends the holding off.
    const bool moving = standing_plans_[static_cast<std::size_t>(giving_way_to)] < kStandingBeforeSwap;
    if (o.goal >= 0 && !o.held && moving &&
        std::any_of(its_way.begin(), its_way.end(), [&](int p) { return zones.conflict(r.type, wanted, o.type, p); })) {
      giving_way_to_[self] = giving_way_to;
      lend_top_priority(giving_way_to);
      if (!back_off(robot, giving_way_to)) take(robot, r.place);
      return true;
    }
  }
  if (standing_plans_[self] < kStandingBeforeSwap) return false;
  std::vector<int> blockers;
  if (check(robot, wanted, blockers) != Check::kBlocked) return false;
  for (const int other : blockers) {
    const PlaceRobot& o = robots_[static_cast<std::size_t>(other)];
    const int its_move = best_move(other);
    if (o.held || its_move < 0 || !zones.conflict(o.type, its_move, r.type, r.place)) continue;
    if (first_move_off(other, robot, path_ahead(robot, wanted), true) >= 0) continue;  // it can be pushed clear
    if (!back_off(robot, other)) return false;
    giving_way_to_[self] = other;
    // The robot let out goes first from now until it has passed: robots further along its way out
    // that would push it back in (more robots queued for the spur) are pushed out of it instead.
    lend_top_priority(other);
    return true;
  }
  return false;
}

void PlacePibt::lend_top_priority(int robot) {
  const double top = *std::max_element(priority_.begin(), priority_.end());
  auto& own = priority_[static_cast<std::size_t>(robot)];
  if (own < top) own = top + 1.0;
}

bool PlacePibt::back_off(int robot, int other) {
  const auto& zones = graph_.zones();
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  const PlaceRobot& o = robots_[static_cast<std::size_t>(other)];
  const int its_move = best_move(other);
  if (its_move < 0 || !zones.conflict(o.type, its_move, r.type, r.place)) return false;
  std::vector<int> blockers;
  const std::vector<int> its_path = path_ahead(other, its_move);
  int move = first_move_off(robot, other, its_path, true);
  if (move < 0) {
    // Boxed in behind (robots queued at a spur's mouth): it backs off through them, lending them
    // its priority, as a robot wanting their places would [Okumura 2022, Algorithm 1].
    move = first_move_off(robot, other, its_path, false);
    if (move < 0) return false;
    if (check(robot, move, blockers) == Check::kBlocked) push_out_of_the_way(robot, move, blockers);
  }
  if (check(robot, move, blockers) != Check::kFree) return false;
  take(robot, move);
  // The other follows at once, before robots of lower priority can take the place.
  if (planned_[static_cast<std::size_t>(other)] < 0 && check(other, its_move, blockers) == Check::kFree) {
    take(other, its_move);
  }
  return true;
}

bool PlacePibt::meets_head_on(int robot, int place) const {
  constexpr double kNear = 10.0;  // metres: farther robots' ways ahead (12 places) do not reach
  const auto& zones = graph_.zones();
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  if (r.goal < 0 || r.held) return false;
  const auto in_way_ahead = [&](int type, int at, const std::vector<int>& way, int way_type) {
    // The way's first place is where its robot stands: one following it is not in its way.
    return std::any_of(way.begin() + (way.empty() ? 0 : 1), way.end(),
                       [&](int q) { return zones.conflict(type, at, way_type, q); });
  };
  std::vector<int> own_way;
  const geometry::Vec2 at = zones.position(r.place);
  // Two robots that back up sort a meeting out by backing off (give_way); one that cannot must
  // not meet another at all. Most fleets have none that cannot: then nothing is looked at.
  const bool against_all = !backs_up(r.type);
  const std::size_t count = against_all ? robots_.size() : forward_only_.size();
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t i = against_all ? k : static_cast<std::size_t>(forward_only_[k]);
    const PlaceRobot& o = robots_[i];
    const auto other = static_cast<int>(i);
    if (other == robot || o.place < 0 || ways_[i].size() < 2) continue;
    if (geometry::distance(zones.position(o.place), at) > kNear) continue;
    if (!in_way_ahead(r.type, place, ways_[i], o.type) || in_way_ahead(r.type, r.place, ways_[i], o.type)) continue;
    if (own_way.empty()) own_way = path_ahead(robot, place);
    const int o_at = planned_[i] >= 0 ? planned_[i] : o.place;
    if (std::any_of(own_way.begin(), own_way.end(), [&](int q) {
          return zones.conflict(r.type, q, o.type, o.place) ||
                 (o_at != o.place && zones.conflict(r.type, q, o.type, o_at));
        })) {
      return true;
    }
  }
  return false;
}

std::vector<int> PlacePibt::path_ahead(int robot, int from) const {
  constexpr std::size_t kPlaces = 12;
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  std::vector<int> path{from};
  while (r.goal >= 0 && path.size() < kPlaces && path.back() != r.goal) {
    int next = -1;
    double cost = graph_.distance(r.type, path.back(), r.goal);
    for (const int candidate : graph_.successors(r.type, path.back())) {
      if (const double c = graph_.distance(r.type, candidate, r.goal); c < cost) {
        next = candidate;
        cost = c;
      }
    }
    if (next < 0) break;
    path.push_back(next);
  }
  return path;
}

int PlacePibt::first_move_off(int robot, int other, const std::vector<int>& path, bool around_standing) {
  constexpr int kReach = 24;
  const auto& zones = graph_.zones();
  const PlaceRobot& r = robots_[static_cast<std::size_t>(robot)];
  const int other_type = robots_[static_cast<std::size_t>(other)].type;
  return search_way(robot, r.place, other, kReach, around_standing,
                    [&](int place) {
                      return place != r.place && std::none_of(path.begin(), path.end(), [&](int p) {
                               return zones.conflict(r.type, place, other_type, p);
                             });
                    })
      .first;
}

std::vector<int> PlacePibt::plan(const std::vector<PlaceRobot>& robots, const ClosedPlaces* closed) {
  robots_ = robots;
  closed_ = closed;
  const std::size_t n = robots.size();
  while (priority_.size() < n) priority_.push_back(std::uniform_real_distribution<double>(0.0, 1.0)(rng_));
  last_place_.resize(n, -1);
  giving_way_to_.resize(n, -1);
  standing_plans_.resize(n, 0);
  planned_.assign(n, -1);
  pushing_.assign(n, 0);
  std::vector<int> order;
  for (std::size_t i = 0; i < n; ++i) {
    const int place = robots[i].place;
    if (place < 0) continue;
    if (place >= graph_.place_count()) {
      throw std::invalid_argument("place planner: robot " + std::to_string(i) + " stands at unknown place " +
                                  std::to_string(place));
    }
    order.push_back(static_cast<int>(i));
    standing_[static_cast<std::size_t>(place)] = static_cast<int>(i);
    if (robots[i].goal >= 0 && robots[i].goal != place && !robots[i].held) priority_[i] += 1.0;
    if (robots[i].place != last_place_[i] || robots[i].held || robots[i].goal < 0) standing_plans_[i] = 0;
  }
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const auto& ra = robots[static_cast<std::size_t>(a)];
    const auto& rb = robots[static_cast<std::size_t>(b)];
    if (ra.held != rb.held) return ra.held;
    // A robot backing off for another goes on doing so before robots behind it push it back in.
    const bool a_gives_way = giving_way_to_[static_cast<std::size_t>(a)] >= 0;
    const bool b_gives_way = giving_way_to_[static_cast<std::size_t>(b)] >= 0;
    if (a_gives_way != b_gives_way) return a_gives_way;
    return priority_[static_cast<std::size_t>(a)] > priority_[static_cast<std::size_t>(b)];
  });
  ways_.assign(n, {});
  forward_only_.clear();
  for (const int robot : order) {
    const PlaceRobot& r = robots[static_cast<std::size_t>(robot)];
    if (!backs_up(r.type)) forward_only_.push_back(robot);
    if (r.held) take(robot, r.place);
  }
  // The ways ahead serve meets_head_on alone, which looks at none without a robot that cannot
  // back up.
  if (!forward_only_.empty()) {
    for (const int robot : order) {
      const PlaceRobot& r = robots[static_cast<std::size_t>(robot)];
      if (!r.held && r.goal >= 0) ways_[static_cast<std::size_t>(robot)] = path_ahead(robot, r.place);
    }
  }
  // A robot waiting beside the roads to enter them, or to sweep its area, pushes those standing
  // in its way out of it.
  for (std::size_t entering = 0; entering < n; ++entering) {
    const PlaceRobot& e = robots[entering];
    if (e.place >= 0 || (e.entering < 0 && !e.pushes_from_area)) continue;
    for (const int robot : order) {
      const PlaceRobot& b = robots[static_cast<std::size_t>(robot)];
      if (planned_[static_cast<std::size_t>(robot)] < 0 &&
          in_way_of(b.type, b.place, static_cast<int>(entering), e.entering)) {
        plan_robot(robot, static_cast<int>(entering), e.entering);
      }
    }
  }
  for (const int robot : order) {
    if (planned_[static_cast<std::size_t>(robot)] < 0) plan_robot(robot, -1, -1);
  }
  for (const int robot : order) {
    const auto i = static_cast<std::size_t>(robot);
    standing_[static_cast<std::size_t>(robots[i].place)] = -1;
    planned_at_[static_cast<std::size_t>(planned_[i])] = -1;
  }
  for (std::size_t i = 0; i < n; ++i) {
    last_place_[i] = robots[i].place;
    if (robots[i].place >= 0 && planned_[i] == robots[i].place) ++standing_plans_[i];
  }
  closed_ = nullptr;
  return planned_;
}

std::string broken_step_rule(const traffic::ConflictZones& zones, const std::vector<PlaceRobot>& robots,
                             const std::vector<int>& next) {
  const std::size_t n = robots.size();
  std::vector<std::vector<std::size_t>> follows(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string robot = "robot " + std::to_string(i);
    if (robots[i].place < 0) continue;
    if (robots[i].held && next[i] != robots[i].place) return robot + " is held but moved";
    for (std::size_t j = 0; j < n; ++j) {
      if (i == j || robots[j].place < 0) continue;
      const PlaceRobot& a = robots[i];
      const PlaceRobot& b = robots[j];
      if (zones.conflict(a.type, a.place, b.type, b.place))
        return robot + " stands at a place conflicting with another's";
      if (zones.conflict(a.type, next[i], b.type, next[j])) return robot + " is planned into conflicting places";
      if (!zones.conflict(a.type, next[i], b.type, b.place)) continue;
      if (next[j] == b.place) return robot + " is planned into a place conflicting with one that stays";
      follows[i].push_back(j);
    }
  }
  // Follows form no cycle: peel off robots that follow nobody left until none is left.
  std::vector<std::uint8_t> gone(n, 0);
  for (bool dropped = true; dropped;) {
    dropped = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (gone[i]) continue;
      bool leads_only_gone = true;
      for (const std::size_t j : follows[i]) leads_only_gone = leads_only_gone && gone[j];
      if (leads_only_gone) {
        gone[i] = 1;
        dropped = true;
      }
    }
  }
  if (std::find(gone.begin(), gone.end(), 0) != gone.end()) return "robots follow one another in a cycle";
  return "";
}

}  // namespace fleet::coordination
