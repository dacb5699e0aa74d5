#pragma once

#include <vector>

#include "geometry/polygon.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

/// The places of a road site bucketed by position: a body's places are looked for among those
/// near it, not among every place of a site of thousands.
class PlaceIndex {
 public:
  explicit PlaceIndex(const traffic::ConflictZones& zones);

  /// Every place whose region, for some vehicle type, may reach within `radius` of `centre` (a
  /// superset: the places whose positions lie within `radius` plus the longest
  /// ConflictZones::reach of any).
  std::vector<int> near(geometry::Vec2 centre, double radius) const;

 private:
  double longest_reach_ = 0.0;
  double cell_ = 1.0;  ///< metres: a bucket's side
  geometry::Vec2 origin_;
  int columns_ = 1;
  int rows_ = 1;
  std::vector<std::vector<int>> buckets_;  ///< row-major, the places whose positions lie in each
};

}  // namespace fleet::coordination
