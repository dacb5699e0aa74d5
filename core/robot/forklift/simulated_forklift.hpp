#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <span>

#include "control/twist.hpp"
#include "localization/ekf.hpp"
#include "localization/marker_localizer.hpp"
#include "map/site.hpp"
#include "sim/forklift_body.hpp"
#include "sim/imu.hpp"
#include "sim/uwb.hpp"

namespace fleet::robot {

struct SimulatedForkliftParams {
  sim::ForkliftParams forklift;
  sim::UwbParams uwb;
  sim::GyroParams gyro;
  localization::EkfParams ekf = localization::EkfParams::tuned();
  /// The thesis's forklifts start at a known heading (always zero [Forklift thesis, section 7.2]); the
  /// filter is then told the start heading instead of resolving it from motion.
  bool known_start_heading = true;
  /// Estimate the gyro bias whenever the robot stands still and subtract it before the EKF.
  bool gyro_standstill_calibration = false;
  /// Use the true pose as the estimate (evaluations that measure control alone).
  bool perfect_localization = false;
  /// Localise by the site's markers and wheel odometry instead of UWB and the gyro (the picker
  /// [Picker thesis, section 4.2.9]); the site's racks hide the markers behind them.
  bool marker_localization = false;
  localization::MarkerLocalizerParams markers;
};

/// A stream of a seeded engine, so that every noise source of every robot is reproducible from
/// one seed and independent of the others.
std::mt19937_64 seeded_engine(std::uint64_t seed, std::uint64_t stream);

/// One simulated forklift as its software sees it: the true body (mecanum kinematics, wheel lag,
/// slip), its UWB tag and gyro, and the EKF fusing them [Forklift thesis, Fig. 4.3]. The software under
/// test reads estimate(); the simulation, collision checks and the truth layer read truth().
///
/// Not thread-safe: one owner steps it.
class SimulatedForklift {
 public:
  SimulatedForklift(const SimulatedForkliftParams& params, const map::Site& site, const geometry::Pose2& start,
                    std::uint64_t seed, std::uint64_t stream);

  /// Stands still so the filter settles before anything depends on it.
  void warm_up(double seconds, double dt);

  /// Applies `cmd` for `dt` seconds: the body moves, the gyro feeds the EKF's prediction and the
  /// commanded velocity its update (what the robot knows it asked for), and a UWB fix updates it
  /// when one is due (20 Hz [Forklift thesis, Table 3.1]). UWB paths crossing `blockers` are NLOS (the
  /// truth); the fix leaves out the ranges of `distrusted` anchors (what the robot believes).
  void step(const control::BodyTwist& cmd, double dt, std::span<const geometry::Polygon> blockers = {},
            std::span<const std::size_t> distrusted = {});

  const geometry::Pose2& truth() const { return body_.pose(); }
  geometry::Pose2 estimate() const;
  /// x, y, yaw covariance of the estimate, row-major.
  std::array<double, 9> covariance() const;
  double localization_score() const;
  double time() const { return t_; }
  const sim::ForkliftBody& body() const { return body_; }
  /// The filter behind estimate(): the UWB one, or the marker localizer's.
  const localization::Ekf& ekf() const { return markers_ ? markers_->ekf() : ekf_; }
  /// The marker localizer, when the robot localises by markers.
  const localization::MarkerLocalizer* marker_localizer() const { return markers_ ? &*markers_ : nullptr; }

 private:
  static localization::EkfParams filter_params(const SimulatedForkliftParams& p, const geometry::Pose2& start);

  bool perfect_;
  sim::ForkliftBody body_;
  sim::UwbTag tag_;
  sim::Gyro gyro_;
  localization::Ekf ekf_;
  std::optional<localization::MarkerLocalizer> markers_;
  static constexpr double kStillDelay = 0.3;        // s after the last motion command
  static constexpr double kBiasTimeConstant = 3.0;  // s of standstill averaging

  double uwb_period_;
  bool calibrate_;
  double still_for_ = 0.0;
  double bias_ = 0.0;
  double next_uwb_ = 0.0;
  double t_ = 0.0;
};

}  // namespace fleet::robot
