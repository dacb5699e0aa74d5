#pragma once

#include <array>
#include <cstddef>
#include <numbers>
#include <span>
#include <string_view>
#include <vector>

#include "geometry/pose.hpp"
#include "planning/lidar_sim.hpp"

namespace fleet::aisle {

/// Where a planar lidar sits on the base and which of its returns count.
struct LidarMount {
  geometry::Pose2 pose;                                     ///< sensor pose in the base frame (x forward, y left)
  double field_of_view = 270.0 * std::numbers::pi / 180.0;  ///< centred on the sensor's x axis
  double min_range = 0.02;                                  ///< metres [Picker thesis, Table 6]
  double max_range = 10.0;                                  ///< metres [Picker thesis, Table 6]
};

/// The picker's two Hokuyo UST-10LX [Picker thesis, section 3.1.1, Table 6]: one on the front-right corner of the
/// base facing 45° right of forward, one on the rear-left corner facing 45° left of backward. Each blind 90° wedge
/// points across the base's own body, so that together they see all around it.
std::array<LidarMount, 2> picker_lidar_mounts(double base_length = 0.65, double base_width = 0.50);

/// The window of the virtual range image around the base centre (the w x h image of [Picker thesis, eq. 4.21]).
/// Returns outside it take no part in the voting [Picker thesis, Algorithm 3, line 9].
struct RangeImageExtent {
  double half_length = 4.0;  ///< along body x, metres
  double half_width = 4.0;   ///< along body y, metres; must exceed the rack width plus 10 % to see both faces
};

/// The virtual range image [Picker thesis, eq. 4.20-4.21]: the returns of every scan as points in the base frame,
/// the base centre at the origin. `scans[i]` comes from the lidar at `mounts[i]`; only its beam angles relative to
/// the sensor and its ranges are read, so a scan's map pose does not matter. Returns outside a mount's field of view
/// or range interval, non-finite ranges and points outside `extent` are dropped.
std::vector<geometry::Vec2> virtual_range_image(std::span<const planning::LidarScan> scans,
                                                std::span<const LidarMount> mounts, const RangeImageExtent& extent);

/// A straight line in the Hesse normal form of [Picker thesis, eq. 4.19] in the base frame:
/// x·cos(theta) + y·sin(theta) = rho.
struct HoughLine {
  double theta = std::numbers::pi / 2.0;  ///< normal angle, [0, pi)
  double rho = 0.0;                       ///< signed distance of the line from the base centre, metres
  int votes = 0;                          ///< the accumulator count of the peak it came from

  /// The line's direction nearest body +x, in [-pi/2, pi/2): θ_line of [Picker thesis, eq. 4.24].
  double direction() const { return theta - std::numbers::pi / 2.0; }
  /// Where the line crosses the body y axis, positive to the left: X_m − w/2 of [Picker thesis, eq. 4.22].
  double lateral_offset() const;
  /// Perpendicular distance of `p` from the line, positive on the side away from the base centre.
  double outward_distance(geometry::Vec2 p) const;
};

/// The Hough transform's parameters [Picker thesis, section 4.3.3.3.2, Algorithm 3].
struct HoughParams {
  double angle_step = std::numbers::pi / 180.0;  ///< θ from 0 to 180° in 1° steps [Picker thesis, Algorithm 3, line 10]
  double rho_step = 0.05;  ///< metres per ρ cell; the seed counts range-image pixels of unstated size
  /// A cell becomes a line when it holds more votes than this [Picker thesis, Algorithm 3, line 18]; the seed uses 20
  /// and 40 (Picker thesis, Fig. 4.42) and fixes it by hand.
  int vote_limit = 40;
  /// A peak must hold the most votes within this many cells in θ and ρ
  /// ("local peaks", Picker thesis, section 4.3.3.2.2), so that one rack face gives one line and not the whole
  /// neighbourhood of its peak.
  int peak_window = 2;
  std::size_t max_lines = 40;  ///< the strongest peaks kept; bounds the pair search
  /// Lines turned further than this from body x cannot be rack faces: the validity limit on e_θ of eq. 4.24.
  double max_heading = std::numbers::pi / 3.0;
};

/// The (θ, ρ) accumulator of [Picker thesis, Algorithm 3, lines 7-22], kept between frames to reuse its storage.
class HoughAccumulator {
 public:
  /// `max_rho`: the largest |ρ| a voting point can produce (the range image's half-diagonal).
  HoughAccumulator(const HoughParams& params, double max_rho);

  /// Clears the counts and lets every point vote once per θ [Picker thesis, Algorithm 3, lines 7-15]. Only the θ rows
  /// that can hold a peak (the heading limit plus the peak window) are voted: the others could never become a rack
  /// face.
  void vote(std::span<const geometry::Vec2> points);
  /// Local peaks above the vote limit within the heading limit, strongest first, at most max_lines.
  std::vector<HoughLine> peaks() const;

  int theta_bins() const { return theta_bins_; }
  int rho_bins() const { return rho_bins_; }
  int votes(int theta_index, int rho_index) const;
  double theta_of(int theta_index) const { return theta_index * params_.angle_step; }
  double rho_of(int rho_index) const { return (rho_index - rho_centre_) * params_.rho_step; }

 private:
  bool is_local_peak(int theta_index, int rho_index) const;

  HoughParams params_;
  int theta_bins_ = 0;
  int rho_bins_ = 0;
  int rho_centre_ = 0;
  int first_voted_ = 0;  ///< θ rows [first_voted_, last_voted_] are voted
  int last_voted_ = 0;
  std::vector<double> cos_;
  std::vector<double> sin_;
  std::vector<int> cells_;
};

/// The line-pair selection [Picker thesis, section 4.3.3.3.2.2-3, eq. 4.23].
struct PairParams {
  double rack_width = 3.0;        ///< face to face [Picker thesis, section 4.3.3.3.2.2]
  double width_tolerance = 0.10;  ///< ±10 % of the rack width [Picker thesis, Algorithm 3, lines 30-31]
  /// Largest angle between the two lines of a pair ("parallel, det ≈ 0", Picker thesis, section 4.3.3.3.2.3).
  double max_parallel_error = 3.0 * std::numbers::pi / 180.0;
  /// Points nearer a line than this count as that face, not as lying between the faces. Without it the lidar noise
  /// puts half of each face's own returns between the lines and the criterion pushes both lines outwards.
  double between_margin = 0.10;
  /// Refits each chosen line to the returns within `refine_band` of it (orthogonal least squares), so that heading
  /// and distance are not quantised to the 1° and ρ cells. Off: the Hough peaks as they are.
  bool refine = true;
  double refine_band = 0.08;
  /// After the fit, each line moves along its normal to the densest part of its returns (a mean shift with this
  /// Gaussian scale, about the range noise). Beams entering the pallet pockets at a slant return from the block
  /// sides just behind the face; they would pull a plain least-squares line 2-3 cm into the rack.
  double mode_scale = 0.02;
};

/// Why a frame gives no pair, or kFound.
enum class PairStatus {
  kFound,
  kTooFewPoints,   ///< fewer returns in the range image than the vote limit
  kNoLines,        ///< no accumulator peak above the vote limit within the heading limit
  kNoLineLeft,     ///< lines on the right only: an open side, or the end of a rack
  kNoLineRight,    ///< lines on the left only
  kNoPairInWidth,  ///< lines on both sides, none spaced within the rack width tolerance
  kNotParallel,    ///< pairs within the width tolerance, none parallel enough
};

std::string_view to_string(PairStatus status);

/// The two rack faces of one frame.
struct RackLinePair {
  PairStatus status = PairStatus::kNoLines;
  HoughLine left;      ///< the face on the base's left (lateral_offset > 0)
  HoughLine right;     ///< the face on the base's right
  double width = 0.0;  ///< perpendicular spacing of the two lines, metres
  /// Direction of the aisle in the base frame (θ_line), rad: the two lines' mean weighted by their votes, so that a
  /// face the other picker hides counts less.
  double heading = 0.0;
  int points_between = 0;      ///< returns between the faces (the other robot, a stray box)
  double criterion = 0.0;      ///< [Picker thesis, eq. 4.23] of the chosen pair
  std::size_t candidates = 0;  ///< lines that entered the pair search

  bool found() const { return status == PairStatus::kFound; }
};

struct RackLineParams {
  RangeImageExtent image;
  HoughParams hough;
  PairParams pair;
};

/// [Picker thesis, eq. 4.23] over every left/right pair within the width tolerance and parallel: the pair with the
/// fewest returns between it and the strongest peaks. `points` is the range image the lines came from.
RackLinePair select_rack_pair(std::span<const HoughLine> lines, std::span<const geometry::Vec2> points,
                              const RackLineParams& params);

/// `line` refitted by orthogonal least squares to the points within `band` of it; `line` itself when fewer than
/// two points are that close. Keeps the votes.
HoughLine refit_line(const HoughLine& line, std::span<const geometry::Vec2> points, double band);

/// `line` moved along its normal, direction kept, to the mode of its points' distances: a mean shift with Gaussian
/// weights of scale `scale` over the points within 5 `scale` of it.
HoughLine shift_to_mode(const HoughLine& line, std::span<const geometry::Vec2> points, double scale);

/// The whole of [Picker thesis, Algorithm 3] for one frame: vote, take the peaks, choose the pair. Holds the
/// accumulator between frames; one owner calls it.
class RackLineDetector {
 public:
  explicit RackLineDetector(const RackLineParams& params = {});

  /// From a virtual range image (see virtual_range_image with the same extent).
  RackLinePair detect(std::span<const geometry::Vec2> points);
  /// From the scans of the lidars at `mounts`.
  RackLinePair detect(std::span<const planning::LidarScan> scans, std::span<const LidarMount> mounts);

  /// The candidate lines of the last frame, strongest first.
  const std::vector<HoughLine>& lines() const { return lines_; }
  const HoughAccumulator& accumulator() const { return accumulator_; }
  const RackLineParams& params() const { return params_; }

 private:
  RackLineParams params_;
  HoughAccumulator accumulator_;
  std::vector<HoughLine> lines_;
};

}  // namespace fleet::aisle
