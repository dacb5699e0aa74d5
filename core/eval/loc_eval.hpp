#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "localization/ekf.hpp"
#include "map/site.hpp"
#include "sim/encoders.hpp"
#include "sim/forklift_body.hpp"
#include "sim/imu.hpp"
#include "sim/uwb.hpp"

namespace fleet::eval {

enum class Trajectory { kSquare, kFigure8, kTableALoop };

/// "square" | "figure8" | "table_a_loop"; nothing for anything else.
std::optional<Trajectory> parse_trajectory(const std::string& name);
std::string to_string(Trajectory t);

/// One localization evaluation: a forklift driven along a reference loop on core/ alone, its
/// sensors recorded once and replayed into one filter per variant, so every variant sees exactly
/// the same data.
struct LocEvalParams {
  Trajectory trajectory = Trajectory::kFigure8;
  double duration = 60.0;      ///< seconds of simulated time
  std::uint64_t seed = 1;      ///< every noise source derives its engine from it
  double nlos_fraction = 0.0;  ///< probability that a range is NLOS (biased), in [0, 1]
  double speed = 0.2;          ///< path speed, m/s (a forklift's pace on the demo table)
  /// Anchors; empty means table_a's four corners at 1 m height.
  std::vector<map::UwbAnchor> anchors;
  sim::ForkliftParams forklift;
  sim::UwbParams uwb;
  sim::GyroParams gyro;
  sim::EncoderParams encoders;    ///< off by default, like the thesis's hardware
  double control_rate_hz = 70.0;  ///< path-tracker rate [Forklift thesis, Table 3.1]
  double physics_dt = 1.0 / 1400.0;
  localization::EkfParams ekf = localization::EkfParams::tuned();
  /// Also run each variant with one beyond-thesis feature off, and the thesis's filter.
  bool variants = true;
};

struct ErrorStats {
  double pos_rmse = 0.0;          ///< metres
  double pos_max = 0.0;           ///< metres
  double heading_rmse_deg = 0.0;  ///< over samples with a resolved heading
  double heading_max_deg = 0.0;
  int samples = 0;
  int heading_samples = 0;
};

struct VariantResult {
  std::string name;  ///< "full", "no_gating", "fixed_q", "fixed_q_no_gating", "no_velocity",
                     ///< "no_heading_init", "encoders" (when on), "seed"
  localization::EkfParams params;
  ErrorStats ekf;
  int fixes_gated = 0;
  double heading_resolved_at = -1.0;  ///< seconds; -1 if never
  double mean_score = 0.0;
};

struct TrackPoint {
  double t = 0.0;
  geometry::Pose2 truth;
  geometry::Pose2 estimate;
  bool valid = false;  ///< estimate initialised (and heading resolved, for the heading error)
};

struct LocEvalResult {
  LocEvalParams params;
  ErrorStats uwb;  ///< raw fixes against the true antenna position (what they measure)
  VariantResult full;
  std::vector<VariantResult> variants;
  int uwb_fixes = 0;
  int uwb_missing = 0;  ///< epochs without a fix (< 3 ranges)
  int ranges = 0;
  int nlos_ranges = 0;
  double range_noise_std = 0.0;  ///< measured std of LOS range errors, metres
  // Series for the plot.
  std::vector<geometry::Pose2> truth;         ///< 70 Hz
  std::vector<geometry::Vec2> uwb_positions;  ///< every fix
  std::vector<geometry::Pose2> ekf_track;     ///< 70 Hz, the full filter, once initialised
  std::vector<map::UwbAnchor> anchors;
};

/// Runs the evaluation. Throws std::invalid_argument for a non-positive duration or an NLOS
/// fraction outside [0, 1].
LocEvalResult run_loc_eval(const LocEvalParams& params);

/// Truth, UWB fixes and EKF track in map coordinates (like [Forklift thesis, Fig. 4.4]), as a standalone SVG.
std::string loc_eval_svg(const LocEvalResult& result);

/// Default anchors: table_a's corners at 1 m.
std::vector<map::UwbAnchor> default_anchors();

}  // namespace fleet::eval
