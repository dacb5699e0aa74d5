#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/polygon.hpp"
#include "planning/lidar_sim.hpp"
#include "planning/occupancy_grid.hpp"

namespace octomap {
class OcTree;
}

namespace fleet::planning {

/// Fixed per layer. Probabilities are OctoMap's log-odds sensor model (Hornung et al. 2013):
/// a hit adds logit(prob_hit), a miss adds logit(prob_miss), values are clamped to
/// [logit(clamp_min), logit(clamp_max)] so the map stays able to change.
struct OctoMapConfiguration {
  double resolution = 0.02;  ///< leaf size, metres
  double prob_hit = 0.7;
  double prob_miss = 0.4;
  double clamp_min = 0.12;
  double clamp_max = 0.97;
  double occupancy_threshold = 0.5;
  double scan_height = 0.1;             ///< z of the scan plane, metres
  geometry::Bounds area;                ///< the site; scans are kept and projected inside it
  double projection_resolution = 0.05;  ///< cell size of the 2D grid the layer projects to
};

/// An OctoMap OcTree fed by planar lidar scans and projected to a 2D occupancy grid
/// (the dynamic grid's sensed layer, beyond the thesis, whose conclusion asks for range sensors
/// [Forklift thesis]).
///
/// `insert_scan` ray-casts in the tree's key space itself instead of calling insertPointCloud:
/// the cells of all 360 beams are de-duplicated in a flat stamp window (not a hash set), and a
/// dense mirror of leaf log-odds over the site skips updates that cannot change a clamped leaf
/// (OctoMap performs the same early abort, but only after searching the tree). Each change of a
/// leaf's occupancy is carried into the projected grid at once, so `sensed()` is always current.
class OctoMapLayer {
 public:
  explicit OctoMapLayer(const OctoMapConfiguration& configuration);
  ~OctoMapLayer();
  OctoMapLayer(const OctoMapLayer&) = delete;
  OctoMapLayer& operator=(const OctoMapLayer&) = delete;

  /// Misses along every beam up to its return (or max range), a hit at each return.
  void insert_scan(const LidarScan& scan);
  /// Writes a 2D grid into the tree: each cell's leaves clamped occupied or free.
  void insert_grid(const OccupancyGrid& grid);

  /// Every leaf of the area free (clamped), as the projection reads a leaf not seen yet: the tree
  /// then holds all the area's leaves from the start, so its memory does not grow with the ground
  /// the robot covers, and a miss on a free leaf is skipped without a tree search.
  void assume_free();

  /// Marks in `out` every cell holding the centre of an occupied leaf, read from the tree itself.
  void project(OccupancyGrid& out) const;
  /// The projection kept up to date by insert_scan / insert_grid (geometry: area at
  /// projection_resolution).
  const OccupancyGrid& sensed() const { return sensed_; }

  /// Occupancy of the leaf at `p`: 1 occupied, 0 free, -1 unknown.
  int leaf_state(geometry::Vec2 p) const;
  std::size_t leaf_count() const;
  const octomap::OcTree& tree() const { return *tree_; }
  const OctoMapConfiguration& configuration() const { return configuration_; }

 private:
  void apply(std::uint16_t kx, std::uint16_t ky, bool hit);
  void set_leaf(std::uint16_t kx, std::uint16_t ky, float log_odds);
  void record(std::uint16_t kx, std::uint16_t ky, float before, float after);

  OctoMapConfiguration configuration_;
  std::unique_ptr<octomap::OcTree> tree_;
  float hit_ = 0.0f, miss_ = 0.0f, clamp_min_ = 0.0f, clamp_max_ = 0.0f, threshold_ = 0.0f;
  std::uint16_t kz_ = 0;
  // Dense mirror of leaf log-odds over the area (NaN: unknown), indexed by key offset.
  std::uint16_t kx0_ = 0, ky0_ = 0;
  int mirror_w_ = 0, mirror_h_ = 0;
  std::vector<float> mirror_;
  // One bit per mirror leaf: clamped free. Most beam cells are, and this 32 times smaller copy
  // answers for them from the cache where the floats would not (a site of 56 m x 33 m: 92 kB).
  std::vector<std::uint64_t> clamped_free_;
  void note_leaf(std::size_t i, float log_odds) {
    const std::uint64_t bit = std::uint64_t{1} << (i & 63);
    if (log_odds <= clamp_min_) {
      clamped_free_[i >> 6] |= bit;
    } else {
      clamped_free_[i >> 6] &= ~bit;
    }
  }
  // Per projected cell: how many of its leaves are occupied.
  OccupancyGrid sensed_;
  std::vector<std::uint16_t> occupied_leaves_;
  // Per scan de-duplication window around the sensor.
  std::vector<std::uint64_t> marked_free_, marked_hit_;  ///< one bit per cell of the window
  int window_size_ = 0;
  std::vector<std::uint32_t> hit_keys_;              ///< packed (kx << 16) | ky
  std::vector<std::pair<double, double>> ends_;      ///< beam endpoints in key coordinates
  std::vector<std::uint8_t> has_hit_;
};

}  // namespace fleet::planning
