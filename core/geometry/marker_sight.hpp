#pragma once

#include <cmath>

#include "geometry/pose.hpp"

namespace fleet::geometry {

/// A marker hangs on a structure's face, facing along its yaw. A camera reads it when its line of
/// sight reaches this point, just in front of the printed face (the structure itself never blocks
/// it); a site whose marker has this point inside a rack is refused, since no camera would read it.
inline Vec2 marker_sight_point(const Pose2& marker) {
  constexpr double kInFrontM = 0.05;
  return {marker.x + kInFrontM * std::cos(marker.yaw), marker.y + kInFrontM * std::sin(marker.yaw)};
}

}  // namespace fleet::geometry
