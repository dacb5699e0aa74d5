#include "monitor/aisle_share.hpp"

#include <algorithm>

namespace fleet::monitor {

namespace {

// A gap in the stamps longer than this (a stopped soak, a restarted agent) is not counted.
constexpr double kLongestStep = 2.0;  // s sim

}  // namespace

std::vector<Aisle> rack_aisles(const std::vector<std::pair<std::string, geometry::Polygon>>& racks, double max_width,
                               double min_length) {
  std::vector<std::pair<std::string, geometry::Bounds>> boxes;
  for (const auto& [id, outline] : racks) {
    if (outline.empty()) continue;
    const geometry::Bounds b = geometry::bounding_box(outline);
    if (std::max(b.max_x - b.min_x, b.max_y - b.min_y) >= min_length) boxes.emplace_back(id, b);
  }
  std::vector<Aisle> aisles;
  const auto overlaps = [](const geometry::Bounds& a, const geometry::Bounds& b) {
    return a.min_x < b.max_x && b.min_x < a.max_x && a.min_y < b.max_y && b.min_y < a.max_y;
  };
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t j = 0; j < boxes.size(); ++j) {
      if (i == j) continue;
      const auto& [a_id, a] = boxes[i];
      const auto& [b_id, b] = boxes[j];
      geometry::Bounds gap;
      // b north of a, or b east of a: each pair once.
      if (b.min_y >= a.max_y) {
        gap = {std::max(a.min_x, b.min_x), a.max_y, std::min(a.max_x, b.max_x), b.min_y};
        if (gap.max_x - gap.min_x < min_length) continue;
      } else if (b.min_x >= a.max_x) {
        gap = {a.max_x, std::max(a.min_y, b.min_y), b.min_x, std::min(a.max_y, b.max_y)};
        if (gap.max_y - gap.min_y < min_length) continue;
      } else {
        continue;
      }
      const double width = std::min(gap.max_x - gap.min_x, gap.max_y - gap.min_y);
      if (width <= 0.0 || width > max_width) continue;
      const bool blocked = std::any_of(boxes.begin(), boxes.end(), [&](const auto& other) {
        return other.first != a_id && other.first != b_id && overlaps(other.second, gap);
      });
      if (!blocked) aisles.push_back({a_id + "|" + b_id, gap});
    }
  }
  return aisles;
}

AisleShareWatch::AisleShareWatch(std::vector<Aisle> aisles, std::vector<std::string> robots)
    : aisles_(std::move(aisles)) {
  for (auto& id : robots) where_.emplace(std::move(id), geometry::Vec2{1e18, 1e18});
}

std::pair<std::string, std::vector<std::string>> AisleShareWatch::shared_now() const {
  for (const Aisle& aisle : aisles_) {
    std::vector<std::string> in;
    for (const auto& [id, at] : where_) {
      if (aisle.box.contains(at)) in.push_back(id);
    }
    if (in.size() >= 2) return {aisle.name, in};
  }
  return {};
}

void AisleShareWatch::note(const std::string& robot_id, geometry::Vec2 position, double sim_time) {
  const auto it = where_.find(robot_id);
  if (it == where_.end()) return;
  if (last_time_ >= 0.0 && !sharing_.empty()) {
    const double step = sim_time - last_time_;
    if (step > 0.0 && step <= kLongestStep) {
      spell_s_ += step;
      shared_s_ += step;
    }
  }
  last_time_ = std::max(last_time_, sim_time);
  it->second = position;
  auto [aisle, robots] = shared_now();
  if (aisle != sharing_ && !aisle.empty()) {
    ++times_;
    spell_s_ = 0.0;
  }
  if (!sharing_.empty() && spell_s_ > longest_s_) {
    longest_s_ = spell_s_;
    longest_aisle_ = sharing_;
    longest_robots_ = sharing_robots_;
  }
  sharing_ = std::move(aisle);
  sharing_robots_ = std::move(robots);
}

}  // namespace fleet::monitor
