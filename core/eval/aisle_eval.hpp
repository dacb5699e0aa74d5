#pragma once
// The picker's aisle following in closed loop [Picker thesis, section 4.3.3]: the simulated mecanum
// base, its two simulated lidars in the simulated rack aisle, the Hough line detector and the
// follower, one control step per scan; and the seed's tests I-III [Picker thesis, Tables 7-9] run
// on it, the figures of `fleetctl pick-eval` and of aisle_test.

#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "aisle/aisle_follower.hpp"
#include "geometry/pose.hpp"
#include "sim/forklift_body.hpp"

namespace fleet::eval {

/// One control step per UST-10LX scan (40 Hz) [Picker thesis, Table 6], s.
inline constexpr double kAisleControlPeriod = 1.0 / 40.0;

/// One picker of a closed-loop run, in the aisle frame (x along the aisle, the right-hand face
/// travelling +x on y = 0, the left-hand face on y = 3).
struct PickerSetup {
  std::string name;
  geometry::Pose2 start;
  aisle::AisleFollowerParams follower;
  double distance = 0.0;  ///< X_f − X_i along the picker's own direction of travel
};

struct PickerTrace {
  PickerSetup setup;
  double travel_yaw = 0.0;   ///< the aisle direction the picker travels along (0 or pi)
  double lateral_ref = 0.0;  ///< aisle-frame y of d_ref from the chosen face
  std::vector<double> time;
  std::vector<geometry::Pose2> pose;
  std::vector<sim::BodyTwist> twist;  ///< the true body twist
  std::vector<bool> lines_found;
};

struct AisleRun {
  std::vector<PickerTrace> traces;
  double min_gap = std::numeric_limits<double>::infinity();  ///< closest approach of two pickers' bodies, m
};

/// Every picker of `setups` in one aisle for `duration` s, each seeing the others in its scans;
/// `seed` drives the wheel slip and the lidars' noise.
AisleRun run_aisle(const std::vector<PickerSetup>& setups, double duration, std::uint64_t seed);

/// Aisle-frame y off d_ref at step `k`, m (simulation truth).
double lateral_error(const PickerTrace& t, std::size_t k);
/// Heading off the direction of travel at step `k`, rad.
double heading_error(const PickerTrace& t, std::size_t k);
/// Distance travelled along the direction of travel at step `k`, m.
double along(const PickerTrace& t, std::size_t k);

/// From when on the picker stays within `lateral_tol` of d_ref and `heading_tol` of the aisle, seconds from the
/// start; infinity when it is still outside at the end.
double settle_time(const PickerTrace& t, double lateral_tol, double heading_tol);

struct AisleFigures {
  double settle = 0.0;         ///< within 3 cm of d_ref and 1 deg of the aisle, for good, s
  double lateral_5cm = 0.0;    ///< first time within 5 cm of d_ref, s
  double heading_1deg = 0.0;   ///< first time within 1 deg of the aisle, s
  double peak_lateral = 0.0;   ///< m/s
  double peak_forward = 0.0;   ///< m/s
  double peak_yaw_rate = 0.0;  ///< rad/s
  double final_lateral = 0.0;  ///< m
  double final_heading = 0.0;  ///< rad
  double final_along = 0.0;    ///< travelled minus requested, m
  double lost_fraction = 0.0;  ///< frames without a line pair
};

AisleFigures aisle_figures(const PickerTrace& t);

/// A picker as in the seed's tests [Picker thesis, Tables 7-9]: the default follower (d_ref = 1 m
/// from the right-hand face), from `start`, asked to drive `distance` along the aisle.
PickerSetup seed_aisle_setup(const std::string& name, geometry::Pose2 start, double distance);

/// One of the seed's aisle-following tests: rack 3 m, d_ref = 1 m from the right-hand face.
struct SeedAisleCase {
  std::string name;    ///< "I", "II", "III +25", "III -25"
  std::string source;  ///< "Table 7", ...
  PickerSetup setup;
  double duration = 0.0;   ///< s simulated
  std::uint64_t seed = 0;  ///< the noise of aisle_test's run; run_seed_aisle_tests(1) uses it
  std::string thesis;      ///< what the thesis reports, in words (it gives plots only)
  /// The convergence time the thesis states, s; NaN when it states none.
  double thesis_settle = std::numeric_limits<double>::quiet_NaN();
};

/// The seed's tests I, II and III (III turned +25 and -25 degrees at the start) [Picker thesis, Tables 7-9].
std::vector<SeedAisleCase> seed_aisle_cases();
/// The case named `name` of seed_aisle_cases(); throws std::out_of_range for an unknown name.
SeedAisleCase seed_aisle_case(const std::string& name);

/// Where the picker must end, against d_ref and the aisle.
struct AisleTargets {
  double final_lateral = 0.02;                      ///< m
  double final_heading = std::numbers::pi / 180.0;  ///< rad, 1 deg
};

struct AisleTestResult {
  SeedAisleCase test;
  AisleFigures figures;
  bool within_target = false;  ///< final |lateral| and |heading| within AisleTargets
};

/// Every case of seed_aisle_cases(), each picker alone in the aisle. With `seed` 1 each runs on
/// its case's own seed (aisle_test's runs); another seed moves every case's by 1000 per step.
std::vector<AisleTestResult> run_seed_aisle_tests(std::uint64_t seed, const AisleTargets& targets = {});

}  // namespace fleet::eval
