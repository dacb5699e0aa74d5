// The TrafficManager's entries onto the roads: where along its route a robot enters, the claims
// of robots waiting beside the roads to enter, and who holds the way in.

#include <algorithm>

#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {

TrafficManager::EntryPoint TrafficManager::entry_point(int robot_id, const std::vector<int>& points,
                                                       double progress) const {
  std::vector<double> cum(points.size(), 0.0);
  for (std::size_t k = 1; k < points.size(); ++k) cum[k] = cum[k - 1] + search_->edge_length(points[k - 1], points[k]);
  std::size_t skip = 0;
  while (skip + 1 < points.size() && cum[skip + 1] <= progress) ++skip;
  const std::vector<int> held = held_places(robot_id);
  const auto holds = [&](std::size_t k) {
    return std::binary_search(held.begin(), held.end(), zones_->place_of(points[k]));
  };
  if (held.empty() || holds(skip)) return {skip, cum[skip]};
  const double reach = footprint_reach(type_of(robot_id));
  for (std::size_t k = skip + 1; k < points.size() && cum[k] <= cum[skip] + reach; ++k) {
    if (holds(k)) return {k, cum[k]};
  }
  return {skip, cum[skip]};
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
    if (!zones_->conflict(type_of(robot_id), place, type_of(id), claim.place)) continue;
    if (self != robots_.end() && closes(self->second, claim.place, type_of(id))) continue;
    out.push_back(id);
  }
  return out;
}

TrafficManager::Entry TrafficManager::entry_for(int point, int robot_id, double now) const {
  Entry entry;
  entry.blockers = holders_in_conflict(point, robot_id);
  std::erase_if(entry.blockers, [&](int id) { return partnered(robot_id, id); });
  const auto self = robots_.find(robot_id);
  const bool holds_entry = self != robots_.end() && self->second.frozen && holds_place_of(robot_id, point);
  if (holds_entry && !entry.blockers.empty()) {
    const auto waits_for_it = [&](int id) {
      const Robot& holder = robots_.at(id);
      return !holder.frozen && holder.wait_since >= 0.0 &&
             std::binary_search(holder.blocked_by.begin(), holder.blocked_by.end(), robot_id);
    };
    if (std::all_of(entry.blockers.begin(), entry.blockers.end(), waits_for_it)) entry.blockers.clear();
  } else if (entry.blockers.empty()) {
    entry.blockers = earlier_entry_claims(point, robot_id, now);
  }
  // Standing on its entry's place, it enters as it stands: what it holds there (its body, the
  // area of its way out across the lanes) stays held until it is past its route's first edge, so
  // nobody is granted into the way it turns out by.
  entry.as_standing = holds_entry && entry.blockers.empty();
  return entry;
}

std::vector<int> TrafficManager::holders_in_conflict(int point, int robot_id) const {
  if (point < 0 || static_cast<std::size_t>(point) >= graph_.points.size()) return {};
  return holders_of(zones_->place_of(point), robot_id);
}

std::vector<int> TrafficManager::holders_of(int place, int robot_id) const {
  std::vector<int> out;
  const int type = type_of(robot_id);
  for (const auto& [id, robot] : robots_) {
    if (id != robot_id && closes(robot, place, type)) out.push_back(id);
  }
  return out;
}

}  // namespace fleet::traffic
