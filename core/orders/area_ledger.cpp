#include "orders/area_ledger.hpp"

#include <algorithm>

namespace fleet::orders {

AreaLedger::AreaLedger(std::vector<Place> places) : places_(std::move(places)) {
  for (const auto& place : places_) holds_[place.id] = false;
}

void AreaLedger::record(Load load) {
  if (auto old = loads_.find(load.id); old != loads_.end() && !old->second.place.empty()) {
    holds_[old->second.place] = false;
  }
  if (!load.place.empty() && load.carried_by.empty()) holds_[load.place] = true;
  loads_[load.id] = std::move(load);
}

const Load* AreaLedger::find(int load_id) const {
  const auto it = loads_.find(load_id);
  return it == loads_.end() ? nullptr : &it->second;
}

const Load* AreaLedger::standing_on(const std::string& place_id) const {
  for (const auto& [id, load] : loads_) {
    if (load.standing_on(place_id)) return &load;
  }
  return nullptr;
}

const Load* AreaLedger::carried_by(const std::string& robot_id) const {
  for (const auto& [id, load] : loads_) {
    if (load.carried_by == robot_id) return &load;
  }
  return nullptr;
}

bool AreaLedger::holds_load(const std::string& place_id) const {
  const auto it = holds_.find(place_id);
  return it != holds_.end() && it->second;
}

void AreaLedger::record_unnamed_drop(const std::string& place_id) {
  holds_[place_id] = true;
}

const Load* AreaLedger::found_empty(const std::string& place_id) {
  if (const Load* standing = standing_on(place_id)) return standing;
  holds_[place_id] = false;
  return nullptr;
}

std::optional<Load> AreaLedger::lifted(const std::string& robot_id, int reported_load_id,
                                       const std::string& pick_place) const {
  const Load* load = find(reported_load_id);
  if (!load) load = standing_on(pick_place);
  if (!load || load->carried_by == robot_id) return std::nullopt;
  Load now = *load;
  now.carried_by = robot_id;
  now.place.clear();
  return now;
}

std::optional<Load> AreaLedger::put_down(int load_id, const geometry::Pose2& pose, const std::string& place_id) const {
  const Load* load = find(load_id);
  if (!load) return std::nullopt;
  Load now = *load;
  now.pose = pose;
  now.carried_by.clear();
  now.place = place_id;
  return now;
}

std::optional<Load> AreaLedger::returned_from(const std::string& robot_id, const std::string& preferred_place) const {
  const Load* carried = carried_by(robot_id);
  if (!carried) return std::nullopt;
  const auto is_free = [&](const Place& p) { return standing_on(p.id) == nullptr; };
  auto place = std::find_if(places_.begin(), places_.end(), [&](const Place& p) { return p.id == preferred_place; });
  if (place == places_.end() || !is_free(*place)) place = std::find_if(places_.begin(), places_.end(), is_free);
  if (place == places_.end()) return std::nullopt;
  Load now = *carried;
  now.pose = place->pose;
  now.place = place->id;
  now.carried_by.clear();
  return now;
}

}  // namespace fleet::orders
