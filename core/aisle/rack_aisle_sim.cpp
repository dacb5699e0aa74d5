#include "aisle/rack_aisle_sim.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace fleet::aisle {

using geometry::Polygon;
using geometry::Vec2;

namespace {

constexpr double kPalletFace = 0.8;  ///< EPAL, the side towards the aisle
/// Blocks across the 800 mm face (EN 13698-1): 100, 145 and 100 mm with 227.5 mm pockets between.
constexpr std::array<std::array<double, 2>, 3> kBlocksAcross{{{0.0, 0.1}, {0.3275, 0.4725}, {0.7, 0.8}}};
/// Block rows along the 1200 mm length, each 145 mm deep.
constexpr std::array<std::array<double, 2>, 3> kBlockRows{{{0.0, 0.145}, {0.5275, 0.6725}, {1.055, 1.2}}};

/// Axis-aligned rectangle, counter-clockwise.
Polygon rectangle(double x0, double x1, double y0, double y1) {
  return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

/// Slab test: the distance along the ray to where it enters the box, +infinity when it misses.
template <typename Box>
double ray_box(Vec2 o, Vec2 d, const Box& b) {
  double enter = 0.0;
  double leave = std::numeric_limits<double>::infinity();
  const auto slab = [&](double origin, double dir, double lo, double hi) {
    if (std::abs(dir) < 1e-12) return origin >= lo && origin <= hi;
    double a = (lo - origin) / dir;
    double c = (hi - origin) / dir;
    if (a > c) std::swap(a, c);
    enter = std::max(enter, a);
    leave = std::min(leave, c);
    return enter <= leave;
  };
  if (!slab(o.x, d.x, b.min_x, b.max_x) || !slab(o.y, d.y, b.min_y, b.max_y)) {
    return std::numeric_limits<double>::infinity();
  }
  return enter;
}

}  // namespace

RackAisle::RackAisle(const RackAisleParams& p) : params_(p) {
  if (!(p.width > 0.0) || !(p.end_x > p.start_x) || !(p.pillar_pitch > p.pillar_size) || !(p.pillar_size > 0.0) ||
      p.pallets_per_bay < 0 || p.block_rows < 1 || p.block_rows > 3 || !(p.rack_depth >= kBlockRows[2][1]) ||
      p.pillar_pitch - p.pillar_size < p.pallets_per_bay * kPalletFace) {
    throw std::invalid_argument("RackAisleParams: sizes must be positive and the pallets must fit between uprights");
  }
  add_side(0.0, -1.0, 0, sides_[0]);
  add_side(p.width, 1.0, 2, sides_[1]);
  const double back = p.rack_depth + p.flue;
  walls_[0] = {p.start_x, p.end_x, -back - 0.1, -back};
  walls_[1] = {p.start_x, p.end_x, p.width + back, p.width + back + 0.1};
  for (auto& boxes : sides_) {
    std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.min_x < b.min_x; });
    for (const Box& b : boxes) longest_box_ = std::max(longest_box_, b.max_x - b.min_x);
  }
}

void RackAisle::add_side(double face_y, double into, int slot_offset, std::vector<Box>& boxes) {
  const RackAisleParams& p = params_;
  const auto box = [&](double x0, double x1, double d0, double d1) {
    const double y0 = face_y + into * d0;
    const double y1 = face_y + into * d1;
    boxes.push_back({x0, x1, std::min(y0, y1), std::max(y0, y1)});
  };
  const double half = 0.5 * p.pillar_size;
  const double gap = (p.pillar_pitch - p.pillar_size - p.pallets_per_bay * kPalletFace) / (p.pallets_per_bay + 1);
  int slot = slot_offset;
  for (double x = p.start_x; x <= p.end_x + 1e-9; x += p.pillar_pitch) {
    box(x - half, x + half, p.pillar_setback, p.pillar_setback + p.pillar_size);
    if (x + p.pillar_pitch > p.end_x + 1e-9) break;
    for (int i = 0; i < p.pallets_per_bay; ++i, ++slot) {
      if (p.empty_every > 0 && slot % p.empty_every == p.empty_every - 1) continue;
      const double x0 = x + half + gap + i * (kPalletFace + gap);
      for (int row = 0; row < p.block_rows; ++row) {
        const auto& depth = kBlockRows[static_cast<std::size_t>(row)];
        for (const auto& across : kBlocksAcross) box(x0 + across[0], x0 + across[1], depth[0], depth[1]);
      }
    }
  }
}

double RackAisle::cast_boxes(const std::vector<Box>& boxes, std::size_t first, std::size_t last, Vec2 origin,
                             Vec2 direction, double best) const {
  for (std::size_t i = first; i < last; ++i) best = std::min(best, ray_box(origin, direction, boxes[i]));
  return best;
}

double RackAisle::cast(Vec2 origin, Vec2 direction, double max_range) const {
  double best = std::numeric_limits<double>::infinity();
  for (const Box& wall : walls_) best = std::min(best, ray_box(origin, direction, wall));
  best = std::min(best, max_range);
  const bool inside = origin.y > 0.0 && origin.y < params_.width;
  if (!inside) {
    // Outside the aisle's free space: no shortcut, every box.
    for (const auto& boxes : sides_) best = cast_boxes(boxes, 0, boxes.size(), origin, direction, best);
  } else if (direction.y != 0.0) {
    // From inside, a beam meets one side only, between where it crosses that face and where it ends.
    const std::size_t side = direction.y < 0.0 ? 0 : 1;
    const double face_y = side == 0 ? 0.0 : params_.width;
    const double to_face = (face_y - origin.y) / direction.y;
    if (to_face < best) {
      const double x_face = origin.x + to_face * direction.x;
      const double x_end = origin.x + best * direction.x;
      const double lo = std::min(x_face, x_end) - longest_box_;
      const double hi = std::max(x_face, x_end);
      const std::vector<Box>& boxes = sides_[side];
      const auto first =
          std::lower_bound(boxes.begin(), boxes.end(), lo, [](const Box& b, double x) { return b.min_x < x; });
      const auto last = std::upper_bound(first, boxes.end(), hi, [](double x, const Box& b) { return x < b.min_x; });
      best = cast_boxes(boxes, static_cast<std::size_t>(first - boxes.begin()),
                        static_cast<std::size_t>(last - boxes.begin()), origin, direction, best);
    }
  }
  return best < max_range ? best : std::numeric_limits<double>::infinity();
}

std::vector<Polygon> RackAisle::polygons() const {
  std::vector<Polygon> out;
  for (const Box& w : walls_) out.push_back(rectangle(w.min_x, w.max_x, w.min_y, w.max_y));
  for (const auto& boxes : sides_) {
    for (const Box& b : boxes) out.push_back(rectangle(b.min_x, b.max_x, b.min_y, b.max_y));
  }
  return out;
}

PickerLidars::PickerLidars(const std::array<LidarMount, 2>& mounts, double range_sigma, std::mt19937_64 rng)
    : mounts_(mounts),
      range_sigma_(range_sigma),
      rng_(rng),
      // 0.25° steps: 1440 beams a turn, of which the 1081 in the 270° field of view are kept [Picker thesis, Table 6].
      lidar_(planning::LidarConfiguration{1440, std::max(mounts[0].max_range, mounts[1].max_range), 0.0}) {
  if (!(range_sigma >= 0.0)) throw std::invalid_argument("PickerLidars: range_sigma must be >= 0");
}

std::array<planning::LidarScan, 2> PickerLidars::scan(const geometry::Pose2& base, const RackAisle& aisle,
                                                      std::span<const geometry::Polygon> others) {
  std::normal_distribution<double> noise(0.0, 1.0);
  std::array<planning::LidarScan, 2> out;
  for (std::size_t s = 0; s < mounts_.size(); ++s) {
    const LidarMount& mount = mounts_[s];
    const geometry::Pose2 sensor = geometry::body_pose_to_map(base, mount.pose);
    planning::LidarScan scan = lidar_.scan(sensor, others);
    if (beam_directions_.size() != scan.ranges.size()) {
      beam_directions_.clear();
      for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
        const double beam = scan.angle_min + static_cast<double>(i) * scan.angle_increment;
        beam_directions_.push_back({std::cos(beam), std::sin(beam)});
      }
    }
    const double cy = std::cos(sensor.yaw);
    const double sy = std::sin(sensor.yaw);
    for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
      double& r = scan.ranges[i];
      const double beam = geometry::normalize_angle(scan.angle_min + static_cast<double>(i) * scan.angle_increment);
      if (std::abs(beam) > 0.5 * mount.field_of_view) {
        r = std::numeric_limits<double>::infinity();
        continue;
      }
      const Vec2 b = beam_directions_[i];  // relative to the sensor, turned by its yaw into the aisle frame
      r = std::min(r, aisle.cast(sensor.position(), {cy * b.x - sy * b.y, sy * b.x + cy * b.y}, mount.max_range));
      if (!std::isfinite(r)) continue;
      r += range_sigma_ * noise(rng_);
      if (r < mount.min_range || r > mount.max_range) r = std::numeric_limits<double>::infinity();
    }
    out[s] = std::move(scan);
  }
  return out;
}

}  // namespace fleet::aisle
