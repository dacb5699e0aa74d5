// The TrafficManager's occupancy tables and grants: who keeps whom out of which place.

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "traffic/traffic_manager.hpp"
#include "traffic/traffic_manager_detail.hpp"

namespace fleet::traffic {

using detail::direction_in;
using detail::kActOnInstruction;
using detail::kInfinity;
using detail::sort_unique;

// ---- occupancy --------------------------------------------------------------------------------------

int TrafficManager::direction_at(const Robot& robot, int index) const {
  return direction_in(*zones_, robot.places, index);
}

int TrafficManager::next_stretch_end(const Robot& robot) const {
  const int last = static_cast<int>(robot.route.size()) - 1;
  int j = robot.grant_end;
  if (j >= last) return last;
  ++j;
  while (j < last && !zones_->stoppable(robot.type, robot.places[static_cast<std::size_t>(j)])) ++j;
  return j;
}

void TrafficManager::mark(const Robot& robot, int slot, int index) {
  const std::uint64_t bit = std::uint64_t{1} << (slot % 64);
  const std::size_t word = static_cast<std::size_t>(slot / 64);
  const int p = robot.places[static_cast<std::size_t>(index)];
  const int types = static_cast<int>(zones_->type_count());
  for (int u = 0; u < types; ++u) {
    if (under_body(robot, p)) {
      occupancy_[typed(u, p) * words_ + word] |= bit;
    } else {
      for (int q : zones_->conflicts(robot.type, p, u)) occupancy_[typed(u, q) * words_ + word] |= bit;
    }
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
  const int types = static_cast<int>(zones_->type_count());
  const std::size_t cells = zones_->place_count() * zones_->type_count();
  words_ = std::max<std::size_t>(1, (slots_.size() + 63) / 64);
  occupancy_.assign(cells * words_, 0);
  spans_.resize(zones_->corridor_count());
  for (auto& spans : spans_) spans.clear();
  for (std::size_t s = 0; s < slots_.size(); ++s) {
    const Robot& robot = *slots_[s];
    const std::uint64_t bit = std::uint64_t{1} << (s % 64);
    for (int k = robot.first_held; k <= robot.grant_end; ++k) mark(robot, static_cast<int>(s), k);
    for (int u = 0; u < types; ++u) {
      for (int p : robot.trail) {
        if (under_body(robot, p)) continue;
        for (int q : zones_->conflicts(robot.type, p, u)) occupancy_[typed(u, q) * words_ + s / 64] |= bit;
      }
      for_each_reach(robot, u, [&](int p) { occupancy_[typed(u, p) * words_ + s / 64] |= bit; });
    }
  }
  close_behind_transporters();
  // Entry claims of robots waiting beside the roads longer than priority_wait.
  entry_closed_.assign(cells, 0);
  for (const auto& [id, claim] : entries_) {
    if (!claim_active(id, claim, now_)) continue;
    for (int u = 0; u < types; ++u) {
      for (int q : zones_->conflicts(type_of(id), claim.place, u)) entry_closed_[typed(u, q)] = 1;
    }
  }
  // Reservations of robots waiting longer than priority_wait: the places of the stretch they wait
  // for, and its corridor direction, against robots that would newly enter them.
  claim_place_.assign(cells, -1);
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
      for (int u = 0; u < types; ++u) {
        for (int q : zones_->conflicts(robot.type, p, u)) {
          if (claim_place_[typed(u, q)] < 0) claim_place_[typed(u, q)] = s;
        }
      }
      const int d = direction_at(robot, j);
      if (d != 0) add_span(zones_->corridor(p), s, d, zones_->corridor_index(p), true);
    }
  }
}

void TrafficManager::close_behind_transporters() {
  pair_closures_.clear();
  if (!configuration_.one_way) return;
  for (const auto& [transporter_id, loader_id] : partners_) {
    const int slot = slot_of(transporter_id);
    if (slot < 0) continue;
    const Robot& robot = *slots_[static_cast<std::size_t>(slot)];
    if (robot.route.empty()) continue;
    // Only the corridor its work is in: driving through others on its way, it closes nothing.
    const int corridor = zones_->corridor(robot.places.back());
    if (corridor < 0) continue;
    const int direction = one_way_.corridor_direction[static_cast<std::size_t>(corridor)];
    if (direction == 0) continue;
    int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
    const auto note = [&](int p) {
      if (zones_->corridor(p) != corridor) return;
      lo = std::min(lo, zones_->corridor_index(p));
      hi = std::max(hi, zones_->corridor_index(p));
    };
    for (int k = robot.first_held; k <= robot.grant_end; ++k) note(robot.places[static_cast<std::size_t>(k)]);
    for_each_reach(robot, robot.type, note);
    if (lo > hi) continue;  // not in it yet
    if (direction > 0) {
      pair_closures_.push_back({corridor, slot, loader_id, std::numeric_limits<int>::min(), lo - 1});
    } else {
      pair_closures_.push_back({corridor, slot, loader_id, hi + 1, std::numeric_limits<int>::max()});
    }
  }
}

void TrafficManager::closure_blockers(int slot, const std::vector<int>& places, int index,
                                      std::vector<int>& blockers) const {
  const int p = places[static_cast<std::size_t>(index)];
  const int corridor = zones_->corridor(p);
  if (corridor < 0) return;
  int before = index - 1;
  while (before >= 0 && places[static_cast<std::size_t>(before)] == p) --before;
  // A robot already inside drives on: only one coming in from outside is kept out.
  if (before < 0 || zones_->corridor(places[static_cast<std::size_t>(before)]) == corridor) return;
  const int at = zones_->corridor_index(p);
  const int self = slots_[static_cast<std::size_t>(slot)]->id;
  for (const PairClosure& closure : pair_closures_) {
    if (closure.corridor != corridor || closure.transporter == slot || at < closure.lo || at > closure.hi) continue;
    if (self == closure.loader_id || partnered(self, closure.loader_id)) continue;
    blockers.push_back(closure.transporter);
  }
}

std::vector<int> TrafficManager::places_under(const geometry::Polygon& body, int type,
                                              std::vector<std::vector<int>>* touched) const {
  // Every place whose region the body touches; but when one region holds the whole body (a robot
  // standing on the road), that place alone: whatever touches the body conflicts with it anyway,
  // and the wider set would close the road to a robot standing close behind or ahead.
  std::vector<int> under;
  int holding = -1;
  double holding_distance = kInfinity;
  geometry::Vec2 centre{};
  for (const auto& corner : body) centre = centre + (1.0 / static_cast<double>(body.size())) * corner;
  const geometry::Bounds box = geometry::bounding_box(body);
  const auto touches = [&](int t, int p) {
    const geometry::Bounds& around = region_bounds_[typed(t, p)];
    if (around.min_x > box.max_x || around.max_x < box.min_x || around.min_y > box.max_y || around.max_y < box.min_y) {
      return false;
    }
    const auto& region = zones_->region(t, p);
    return std::any_of(region.begin(), region.end(), [&](const geometry::Polygon& piece) {
      return geometry::convex_polygons_distance(piece, body) <= 0.0;
    });
  };
  const int types = static_cast<int>(zones_->type_count());
  if (touched) touched->assign(static_cast<std::size_t>(types), {});
  for (std::size_t p = 0; p < zones_->place_count(); ++p) {
    if (touched) {
      for (int t = 0; t < types; ++t) {
        if (t != type && touches(t, static_cast<int>(p)))
          (*touched)[static_cast<std::size_t>(t)].push_back(static_cast<int>(p));
      }
    }
    if (!touches(type, static_cast<int>(p))) continue;
    const auto& region = zones_->region(type, static_cast<int>(p));
    under.push_back(static_cast<int>(p));
    if (touched) (*touched)[static_cast<std::size_t>(type)].push_back(static_cast<int>(p));
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

bool TrafficManager::entry_closes(const std::vector<int>& places, int index, int type) const {
  // Closed to robots coming from outside the claim's places; one inside may drive on and out.
  const auto closed = [&](int k) { return entry_closed_[typed(type, places[static_cast<std::size_t>(k)])] != 0; };
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
  const int type = slots_[static_cast<std::size_t>(slot)]->type;
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
  collect(&occupancy_[typed(type, p) * words_]);
  // Where its own body already stands, a robot drives on past holders that wait for it: the
  // conflict is one of where the two stand (a forklift backing out of a place onto the lane just
  // ahead of a robot granted up to its old spot), and they stay put while it moves away.
  const Robot& self = *slots_[static_cast<std::size_t>(slot)];
  if (under_body_for(self, p, type)) {
    const auto waits_for_self = [&](int w) {
      const Robot& other = *slots_[static_cast<std::size_t>(w)];
      return other.wait_since >= 0.0 &&
             std::find(other.blocked_by.begin(), other.blocked_by.end(), self.id) != other.blocked_by.end();
    };
    blockers.erase(
        std::remove_if(blockers.begin() + static_cast<std::ptrdiff_t>(before), blockers.end(), waits_for_self),
        blockers.end());
  }
  auto claimed_by = [&](int w) {
    if (w < 0 || w == slot) return;
    const Robot& claimant = *slots_[static_cast<std::size_t>(w)];
    // The robots a claimant waits for must stay free to move out of its way.
    if (std::find(claimant.blocked_by.begin(), claimant.blocked_by.end(), self.id) != claimant.blocked_by.end()) return;
    if (higher_priority(self, claimant)) return;
    blockers.push_back(w);
  };
  // The claimant of an entry is off the graph: it blocks without being a robot to wait for
  // (extend notes it in kept_out_by).
  if (entry_closes(places, index, type)) return false;
  // A reserved place is closed to robots coming from outside the reservation; one inside may leave.
  const int claimant = claim_place_[typed(type, p)];
  if (claimant >= 0 &&
      (index == 0 || claim_place_[typed(type, places[static_cast<std::size_t>(index - 1)])] != claimant)) {
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
  if (zones_->has_opposite_lanes()) opposite_lane_blockers(slot, places, index, d, blockers);
  if (!pair_closures_.empty()) closure_blockers(slot, places, index, blockers);
  // Nothing its partner holds keeps it (set_partners): the two move as one, and each one's own
  // safety check keeps it off the other's body.
  if (!partners_.empty()) {
    const auto partner = [&](int w) { return partnered(self.id, slots_[static_cast<std::size_t>(w)]->id); };
    blockers.erase(std::remove_if(blockers.begin() + static_cast<std::ptrdiff_t>(before), blockers.end(), partner),
                   blockers.end());
  }
  return blockers.size() == before;
}

void TrafficManager::opposite_lane_blockers(int slot, const std::vector<int>& places, int index, int direction,
                                            std::vector<int>& blockers) const {
  const int p = places[static_cast<std::size_t>(index)];
  const int c = zones_->corridor(p);
  if (c < 0) return;
  const int at = zones_->corridor_index(p);
  int before_index = index - 1;
  while (before_index >= 0 && places[static_cast<std::size_t>(before_index)] == p) --before_index;
  const int before = before_index < 0 ? -1 : places[static_cast<std::size_t>(before_index)];
  const int type = slots_[static_cast<std::size_t>(slot)]->type;
  for (int other_type = 0; other_type < static_cast<int>(zones_->type_count()); ++other_type) {
    for (const OppositeLane& lane : zones_->opposite_lanes(type, c, other_type)) {
      if (at < lane.lo || at > lane.hi) continue;
      // Only a robot entering the stretch waits; one inside must be free to drive on out of it.
      const bool inside_before = before >= 0 && zones_->corridor(before) == c &&
                                 zones_->corridor_index(before) >= lane.lo && zones_->corridor_index(before) <= lane.hi;
      if (inside_before) continue;
      for (const CorridorSpan& span : spans_[static_cast<std::size_t>(lane.corridor)]) {
        if (span.slot == slot || span.reserved || slots_[static_cast<std::size_t>(span.slot)]->type != other_type)
          continue;
        if (span.hi < lane.other_lo || span.lo > lane.other_hi) continue;  // not in the stretch
        const bool towards =
            direction == 0 || span.direction == 0 || lane.sign == 0 || span.direction * lane.sign == -direction;
        if (towards) blockers.push_back(span.slot);
      }
    }
  }
}

void TrafficManager::extend(Robot& robot, int slot) {
  const int last = static_cast<int>(robot.route.size()) - 1;
  robot.blocked = false;
  robot.blocked_by.clear();
  robot.kept_out_by.clear();
  if (robot.frozen) return;
  if (!robot.giving_way_to.empty()) {
    const bool still_stopped = std::any_of(robot.giving_way_to.begin(), robot.giving_way_to.end(), [&](int id) {
      return std::binary_search(robot.stopped_for.begin(), robot.stopped_for.end(), id);
    });
    if (still_stopped) return;
    robot.giving_way_to.clear();
  }
  const double target = robot.progress + configuration_.lookahead;
  std::vector<int> blockers;
  std::vector<int> in_arrival;  // ids
  while (robot.grant_end < last && robot.cum[static_cast<std::size_t>(robot.grant_end)] < target) {
    int j = robot.grant_end + 1;
    bool free = true;
    for (;; ++j) {
      if (!place_free_for(slot, robot.places, j, blockers)) {
        free = false;
        break;
      }
      if (arrival_pending(robot, j)) {
        in_arrival = arrival_blockers(robot);
        if (!in_arrival.empty()) {
          free = false;
          break;
        }
      }
      const int place = robot.places[static_cast<std::size_t>(j)];
      if (j == last || (zones_->stoppable(robot.type, place) && !stop_kept_clear(robot, place))) break;
    }
    if (!free) {
      robot.blocked = true;
      sort_unique(blockers);
      for (int b : blockers) robot.blocked_by.push_back(slots_[static_cast<std::size_t>(b)]->id);
      robot.blocked_by.insert(robot.blocked_by.end(), in_arrival.begin(), in_arrival.end());
      sort_unique(robot.blocked_by);
      if (entry_closes(robot.places, j, robot.type)) {
        const int p = robot.places[static_cast<std::size_t>(j)];
        for (const auto& [id, claim] : entries_) {
          if (claim_active(id, claim, now_) && zones_->conflict(robot.type, p, type_of(id), claim.place)) {
            robot.kept_out_by.push_back(id);
          }
        }
      }
      break;
    }
    for (int k = robot.grant_end + 1; k <= j; ++k) mark(robot, slot, k);
    robot.grant_end = j;
    if (arrival_pending(robot, j)) {
      robot.arrival_held = true;
      const std::uint64_t bit = std::uint64_t{1} << (slot % 64);
      for (int u = 0; u < static_cast<int>(zones_->type_count()); ++u) {
        for (int p : robot.arrival_reach[static_cast<std::size_t>(u)]) {
          occupancy_[typed(u, p) * words_ + static_cast<std::size_t>(slot / 64)] |= bit;
        }
      }
    }
  }
}

bool TrafficManager::stopped_at_grant_end(const Robot& robot) const {
  return robot.progress >= robot.cum[static_cast<std::size_t>(robot.grant_end)] - configuration_.stop_tolerance;
}

int TrafficManager::reached_index(const Robot& robot) const {
  int reached = robot.first_held;
  while (reached < robot.grant_end && robot.cum[static_cast<std::size_t>(reached)] + 1e-6 < robot.progress) ++reached;
  return reached;
}

int TrafficManager::anchor_index(const Robot& robot) const {
  if (stopped_at_grant_end(robot)) return robot.grant_end;
  int k = robot.grant_end;
  const double behind = robot.progress + configuration_.stop_tolerance;
  while (k > robot.first_held && robot.cum[static_cast<std::size_t>(k)] > behind) --k;
  return k;
}

std::vector<int> TrafficManager::holders_in_area(int robot_id, const geometry::Polygon& area,
                                                 const std::map<int, geometry::Polygon>& bodies) const {
  // A robot's held place conflicts with the area when its region, of that robot's type, touches it.
  std::vector<std::vector<int>> touched;
  places_under(area, type_of(robot_id), &touched);
  std::vector<int> out;
  for (const auto& [id, robot] : robots_) {
    // A robot that waits for this one stays where it is (its grant ends short of this one's
    // hold): like a standing one it counts by its body.
    const bool waits_for_it =
        robot.wait_since >= 0.0 && std::binary_search(robot.blocked_by.begin(), robot.blocked_by.end(), robot_id);
    if (id == robot_id || ((robot.frozen || waits_for_it) && bodies.contains(id))) continue;
    const auto& near = touched[static_cast<std::size_t>(robot.type)];
    const std::vector<int> held = held_places(id);
    if (std::any_of(held.begin(), held.end(),
                    [&](int place) { return std::binary_search(near.begin(), near.end(), place); })) {
      out.push_back(id);
    }
  }
  for (const auto& [id, body] : bodies) {
    if (id != robot_id && geometry::convex_polygons_overlap(body, area)) out.push_back(id);
  }
  // Robots turning into a place beside the road (or backing out of one) sweep their arrival area.
  for (const auto& [id, robot] : robots_) {
    if (id == robot_id || robot.frozen) continue;
    const bool in_arrival = robot.arrival_held && geometry::convex_polygons_overlap(robot.arrival_area, area);
    const bool backing_out = !robot.body_reach.empty() && !robot.body_polygon.empty() &&
                             geometry::convex_polygons_overlap(robot.body_polygon, area);
    if (in_arrival || backing_out) out.push_back(id);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

}  // namespace fleet::traffic
