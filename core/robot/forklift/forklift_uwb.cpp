// What shadows the UWB ranges of a forklift: switched-on obstacles between an anchor and the tag,
// and neighbours close enough to the tag to block the ray.
#include <algorithm>
#include <limits>

#include "robot/forklift/forklift.hpp"

namespace fleet::robot {

using geometry::Vec2;

std::vector<geometry::Polygon> Forklift::uwb_blockers() const {
  std::vector<geometry::Polygon> out = nav_.enabled_obstacles();
  // A neighbour shadows an anchor only near the tag: the ray from an anchor at height z_a to the
  // tag at z_t rises above a robot of height h within (h - z_t) / (z_a - z_t) of the horizontal
  // distance. Anchors stand about 1 m high around the table, 2-4 m away, so only a robot within
  // a few centimetres to a dozen of our antenna blocks a range; treating its 2D outline as a wall
  // to every anchor would shadow most of the table.
  const Vec2 tag = sim_.estimate().position();
  // metres: (0.15 - 0.10) / (1.0 - 0.10) x 3 m, rounded up, on the table; it scales with the robot.
  const double reach = config_.uwb_shadow_reach;
  for (const auto& n : nav_.neighbours()) {
    const auto polygon = geometry::footprint_polygon(n.pose, n.footprint);
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec2& corner : polygon) nearest = std::min(nearest, geometry::distance(corner, tag));
    if (nearest <= reach || geometry::contains(polygon, tag)) out.push_back(polygon);
  }
  return out;
}

std::vector<std::size_t> Forklift::shadowed_anchors() const {
  std::vector<std::size_t> out;
  if (config_.anchor_shadow_margin < 0.0) return out;
  const auto& anchors = nav_.site().site.uwb_anchors;
  const Vec2 tag = geometry::body_to_map(sim_.estimate(), config_.sim.uwb.antenna_offset);
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    const Vec2 anchor{anchors[i].x, anchors[i].y};
    for (const auto& o : nav_.site().site.static_obstacles) {
      if (nav_.obstacle_enabled(o.id) &&
          geometry::segment_polygon_distance(anchor, tag, o.polygon) <= config_.anchor_shadow_margin) {
        out.push_back(i);
        break;
      }
    }
  }
  // Three ranges fix a position; with fewer left, a biased fix still beats none for long.
  if (anchors.size() - out.size() < 3) out.clear();
  return out;
}

}  // namespace fleet::robot
