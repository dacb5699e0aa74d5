#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "map/site.hpp"

namespace fleet::sim {

inline constexpr double kSpeedOfLight = 299'792'458.0;  // m/s

// ---------------------------------------------------------------------------------------------
// Ranging: simulated message exchanges [Forklift thesis, sections 2.1.2-2.1.3]

/// One ranging exchange between initiator A (the tag) and responder B (an anchor), in true time.
/// A device whose crystal is off by e measures a true interval T as T (1 + e).
struct RangingExchange {
  double time_of_flight = 0.0;  ///< t_p, seconds
  double reply_a = 0.0;         ///< t_replyA, true seconds
  double reply_b = 0.0;         ///< t_replyB, true seconds
  double drift_a = 0.0;         ///< e_A, dimensionless (1 ppm = 1e-6)
  double drift_b = 0.0;         ///< e_B
};

/// Receive-timestamp jitter applied to each of the exchange's reception times (leading-edge
/// detection noise). Transmissions are scheduled, so their timestamps are exact.
struct TimestampNoise {
  double rx_std = 0.0;  ///< seconds
};

/// Plain two-way ranging: t_p = (t_round (1+e_A) - t_replyB (1+e_B)) / 2 [Forklift thesis, eq. 2.2].
double twr_time_of_flight(const RangingExchange& ex, const TimestampNoise& noise, std::mt19937_64& rng);

/// Symmetric double-sided two-way ranging [Forklift thesis, eq. 2.6]: the four intervals measured by the two
/// clocks, combined as ((t_roundA - t_replyA) + (t_roundB - t_replyB)) / 4.
double sds_twr_time_of_flight(const RangingExchange& ex, const TimestampNoise& noise, std::mt19937_64& rng);

/// Asymmetric double-sided two-way ranging, beyond the thesis (Neirynck, Luk, McLaughlin, "An
/// alternative double-sided two-way ranging method", WPNC 2016; the formula of the DW1000 user
/// manual): t_p = (t_roundA t_roundB - t_replyA t_replyB) / (t_roundA + t_roundB + t_replyA +
/// t_replyB). The same four intervals as eq. 2.6, but the clock-drift error is
/// t_p (e_A + e_B) / 2 whatever the reply times, instead of eq. 2.8's (t_replyB - t_replyA)
/// (e_A - e_B) / 4, which only vanishes when both devices reply after exactly the same delay.
/// Its timestamp-noise weights are those of eq. 2.6 to first order, so the range noise is the same.
double ads_twr_time_of_flight(const RangingExchange& ex, const TimestampNoise& noise, std::mt19937_64& rng);

/// Clock-drift error predicted by eq. 2.4 (TWR) and eq. 2.7 / 2.8 (SDS-TWR) [Forklift thesis].
double twr_drift_error(const RangingExchange& ex);           // eq. 2.4
double sds_twr_drift_error_full(const RangingExchange& ex);  // eq. 2.7
double sds_twr_drift_error(const RangingExchange& ex);       // eq. 2.8
/// Exact clock-drift error of ads_twr_time_of_flight: t_p (2 (1+e_A)(1+e_B) / (2 + e_A + e_B) - 1).
double ads_twr_drift_error(const RangingExchange& ex);

// ---------------------------------------------------------------------------------------------
// Multilateration

struct AnchorRange {
  std::size_t anchor = 0;  ///< index into the anchor list
  double range = 0.0;      ///< measured slant range, metres
};

struct MultilaterationParams {
  double tag_height = 0.10;  ///< antenna height above the floor, metres (known, not solved)
  double range_std = 0.05;   ///< assumed range noise for the covariance, metres
  int max_iterations = 20;
  double tolerance = 1e-6;  ///< stop when the step is shorter, metres
  /// Anchors closer than this to a common line leave the side of the line undecided.
  double collinear_tolerance = 0.05;  ///< metres
};

/// A position fix of the UWB antenna in the map frame [Forklift thesis, eq. 4.10].
struct UwbFix {
  double stamp = 0.0;                                        ///< seconds, sensor clock
  geometry::Vec2 position;                                   ///< antenna position, metres
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Identity();  ///< m^2
  int ranges_used = 0;
  double residual_rms = 0.0;  ///< metres
  /// True when the anchors used lie on a line: the fix may be the mirror image of the truth; the
  /// covariance then covers both candidates.
  bool mirror_ambiguous = false;
};

/// Gauss-Newton (Levenberg damped) least squares over the ranges, with the covariance
/// sigma^2 (J^T J)^-1, where sigma is the larger of the assumed range noise and the residual
/// scatter. Returns nothing with fewer than 3 ranges or when the solve fails.
/// `initial_guess` (e.g. the previous fix) picks the side of the line for collinear anchors.
std::optional<UwbFix> solve_multilateration(const std::vector<map::UwbAnchor>& anchors,
                                            std::span<const AnchorRange> ranges, const MultilaterationParams& params,
                                            std::optional<geometry::Vec2> initial_guess = {});

// ---------------------------------------------------------------------------------------------
// The UWB tag on a forklift

enum class NlosMode { kBias, kDrop };

/// How the tag turns an exchange's four intervals into a time of flight.
enum class RangingFormula {
  kSdsTwr,  ///< [Forklift thesis, eq. 2.6]: biased by eq. 2.8 when the reply delays differ
  kAdsTwr,  ///< asymmetric double-sided (see ads_twr_time_of_flight): no reply-delay bias
};

struct UwbParams {
  double rate_hz = 20.0;                     ///< [Forklift thesis, Table 3.1]
  geometry::Vec2 antenna_offset{0.05, 0.0};  ///< (a, b) in the body frame [Forklift thesis, eq. 4.12]
  double clock_ppm_std = 5.0;                ///< crystal offset of each device after trimming, ppm
  double reply_a = 300e-6;                   ///< tag's reply delay, s
  double reply_b = 320e-6;                   ///< anchors' reply delay, s (asymmetry drives eq. 2.8)
  /// The thesis's eq. 2.6 leaves every anchor's range off by a constant c (t_replyB - t_replyA)
  /// (e_A - e_B) / 4: with 20 us of asymmetry and 5 ppm crystals about 1 cm each, so a fix carries
  /// a steady bias of the same size that no filter can average away. The asymmetric formula
  /// removes it from the same messages, so it is the default; kSdsTwr reproduces the thesis.
  RangingFormula ranging = RangingFormula::kAdsTwr;
  /// Receive-timestamp jitter. SDS-TWR combines three receptions with weights 2, 1, 1 over 4, so
  /// the range noise is c * rx_std * sqrt(6) / 4: 0.272 ns gives 5.0 cm.
  double rx_timestamp_std = 0.272e-9;  ///< seconds
  double max_range = 30.0;             ///< ranges beyond this are lost, metres
  NlosMode nlos_mode = NlosMode::kBias;
  /// Extra path length of a blocked or reflected signal: exponential with this mean, plus the
  /// minimum. Always positive: NLOS never shortens a UWB range.
  double nlos_bias_mean = 0.30;  ///< metres
  double nlos_bias_min = 0.05;   ///< metres
  /// Probability that any range is NLOS regardless of geometry (people, clutter not on the map).
  double random_nlos_probability = 0.0;
  MultilaterationParams solver;
};

struct RangeReading {
  std::size_t anchor = 0;
  double range = 0.0;
  double true_range = 0.0;
  bool nlos = false;
};

/// The tag on one forklift, ranging to every anchor of the site by simulated SDS-TWR.
class UwbTag {
 public:
  /// Draws the crystal offsets of the tag and of every anchor from `rng`.
  UwbTag(std::vector<map::UwbAnchor> anchors, const UwbParams& params, std::mt19937_64 rng);

  /// Anchors taken from the site file.
  UwbTag(const map::Site& site, const UwbParams& params, std::mt19937_64 rng);

  /// Ranges from the antenna at body pose `truth`. A range whose straight anchor-tag path crosses
  /// one of `blockers` (enabled static obstacles, other robots' footprints) is NLOS: biased
  /// or dropped by `nlos_mode`.
  std::vector<RangeReading> measure_ranges(const geometry::Pose2& truth,
                                           std::span<const geometry::Polygon> blockers = {});

  /// Ranges, then a fix (nothing when fewer than 3 ranges remain). The previous fix seeds the
  /// solver. The ranges of `distrusted` anchors (those the robot's map shows behind an obstacle)
  /// are measured but left out of the fix.
  std::optional<UwbFix> measure(const geometry::Pose2& truth, double stamp,
                                std::span<const geometry::Polygon> blockers = {},
                                std::span<const std::size_t> distrusted = {});

  /// Where the antenna of a body at `pose` is [Forklift thesis, eq. 4.11].
  geometry::Vec2 antenna_position(const geometry::Pose2& pose) const;

  const std::vector<map::UwbAnchor>& anchors() const { return anchors_; }
  const UwbParams& params() const { return params_; }

 private:
  std::vector<map::UwbAnchor> anchors_;
  UwbParams params_;
  std::mt19937_64 rng_;
  double tag_drift_ = 0.0;
  std::vector<double> anchor_drift_;
  std::optional<geometry::Vec2> last_fix_;
};

}  // namespace fleet::sim
