#include "coordination/place_index.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::coordination {

PlaceIndex::PlaceIndex(const traffic::ConflictZones& zones) {
  const int places = static_cast<int>(zones.place_count());
  for (int type = 0; type < static_cast<int>(zones.type_count()); ++type) {
    for (int place = 0; place < places; ++place) longest_reach_ = std::max(longest_reach_, zones.reach(type, place));
  }
  if (places == 0) return;
  geometry::Vec2 low = zones.position(0);
  geometry::Vec2 high = low;
  for (int place = 1; place < places; ++place) {
    const geometry::Vec2 p = zones.position(place);
    low = {std::min(low.x, p.x), std::min(low.y, p.y)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y)};
  }
  // Buckets about a body's size: a look-up visits a few, each holding a few places.
  cell_ = std::max(1.0, longest_reach_);
  origin_ = low;
  columns_ = static_cast<int>((high.x - low.x) / cell_) + 1;
  rows_ = static_cast<int>((high.y - low.y) / cell_) + 1;
  buckets_.resize(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_));
  for (int place = 0; place < places; ++place) {
    const geometry::Vec2 p = zones.position(place);
    const int column = static_cast<int>((p.x - origin_.x) / cell_);
    const int row = static_cast<int>((p.y - origin_.y) / cell_);
    buckets_[static_cast<std::size_t>(row * columns_ + column)].push_back(place);
  }
}

std::vector<int> PlaceIndex::near(geometry::Vec2 centre, double radius) const {
  std::vector<int> found;
  if (buckets_.empty()) return found;
  const double r = radius + longest_reach_;
  const auto clamp_column = [&](double x) {
    return std::clamp(static_cast<int>(std::floor(x / cell_)), 0, columns_ - 1);
  };
  const auto clamp_row = [&](double y) { return std::clamp(static_cast<int>(std::floor(y / cell_)), 0, rows_ - 1); };
  const int c0 = clamp_column(centre.x - r - origin_.x);
  const int c1 = clamp_column(centre.x + r - origin_.x);
  const int r0 = clamp_row(centre.y - r - origin_.y);
  const int r1 = clamp_row(centre.y + r - origin_.y);
  for (int row = r0; row <= r1; ++row) {
    for (int column = c0; column <= c1; ++column) {
      const auto& bucket = buckets_[static_cast<std::size_t>(row * columns_ + column)];
      found.insert(found.end(), bucket.begin(), bucket.end());
    }
  }
  return found;
}

}  // namespace fleet::coordination
