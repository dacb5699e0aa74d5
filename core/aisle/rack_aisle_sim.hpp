#pragma once

#include <array>
#include <random>
#include <span>
#include <vector>

#include "aisle/hough_lines.hpp"
#include "geometry/polygon.hpp"
#include "planning/lidar_sim.hpp"
#include "sim/forklift_body.hpp"
#include "sim/summit_xls.hpp"  // the picker's base: sim::summit_xls_body_params()

namespace fleet::aisle {

/// A straight aisle between two pallet racks as the picker's lidars see it, at the height of the pallet blocks.
/// Aisle frame: x along the aisle, the right-hand face (travelling +x) on y = 0, the left-hand face on y = width.
/// Pallets stand with their 800 mm side to the aisle, fronts on the face line; an EPAL pallet's pockets run through
/// its whole length, so beams entering a pocket, or an empty slot, return from deep in the rack or from the wall
/// behind it: the range spikes of hollow pallets [Picker thesis, section 4.3.3.3].
struct RackAisleParams {
  double width = 3.0;            ///< face to face [Picker thesis, Tables 7-9]
  double start_x = -15.0;        ///< metres
  double end_x = 15.0;           ///< metres
  double pillar_pitch = 3.5;     ///< uprights every 3.5 m [Picker thesis, section 4.2.9, Exp. 2]
  double pillar_size = 0.10;     ///< square uprights, metres
  double pillar_setback = 0.05;  ///< the uprights stand this far behind the pallet fronts, metres
  int pallets_per_bay = 3;       ///< spread evenly over the clear span between two uprights
  int empty_every = 4;           ///< every n-th pallet slot along a side is empty; 0: none
  int block_rows = 3;            ///< rows of blocks modelled front to back (1: the front row only)
  double rack_depth = 1.2;       ///< EPAL length, metres
  double flue = 0.2;             ///< free space from the back of the pallets to the wall behind, metres
};

/// The aisle's obstacles: uprights and pallet blocks (EPAL 800 mm face: blocks 100/145/100 mm, pockets 227.5 mm),
/// and the walls behind both racks. Casts rays itself: the blocks of each side are sorted along the aisle, so a beam
/// from inside the aisle tests only those near where it crosses a face, not the thousand edges of the whole aisle.
class RackAisle {
 public:
  explicit RackAisle(const RackAisleParams& params = {});

  /// Distance along the ray from `origin` in the unit direction `direction` to the first obstacle; +infinity when
  /// there is none within `max_range`.
  double cast(geometry::Vec2 origin, geometry::Vec2 direction, double max_range) const;

  /// Every obstacle as a closed counter-clockwise polygon, for planning::LidarSim, drawing or collision checks.
  std::vector<geometry::Polygon> polygons() const;
  const RackAisleParams& params() const { return params_; }

 private:
  struct Box {
    double min_x, max_x, min_y, max_y;
  };
  void add_side(double face_y, double into, int slot_offset, std::vector<Box>& boxes);
  double cast_boxes(const std::vector<Box>& boxes, std::size_t first, std::size_t last, geometry::Vec2 origin,
                    geometry::Vec2 direction, double best) const;

  RackAisleParams params_;
  std::array<std::vector<Box>, 2> sides_;  ///< right (y ≤ 0) and left (y ≥ width), each sorted by min_x
  std::array<Box, 2> walls_;
  double longest_box_ = 0.0;  ///< along x, bounds the search window
};

/// The simulated pair of Hokuyo UST-10LX of the picker [Picker thesis, section 3.1.1, Table 6]: 0.25° steps over
/// 270°, 0.02-10 m, range noise. The racks come from RackAisle::cast, anything else (the other pickers) from
/// planning::LidarSim; beams outside a sensor's field of view or range come back as +infinity.
class PickerLidars {
 public:
  /// `range_sigma`: Gaussian range noise, metres (the data sheet's ±40 mm read as a 2σ bound gives 0.02).
  PickerLidars(const std::array<LidarMount, 2>& mounts, double range_sigma, std::mt19937_64 rng);

  /// One scan per lidar with the base at `base` in the aisle frame; `others` are further obstacles (polygons).
  std::array<planning::LidarScan, 2> scan(const geometry::Pose2& base, const RackAisle& aisle,
                                          std::span<const geometry::Polygon> others = {});

  const std::array<LidarMount, 2>& mounts() const { return mounts_; }

 private:
  std::array<LidarMount, 2> mounts_;
  double range_sigma_;
  std::mt19937_64 rng_;
  planning::LidarSim lidar_;
  std::vector<geometry::Vec2> beam_directions_;  ///< unit vectors of the beams in the sensor frame
};

}  // namespace fleet::aisle
