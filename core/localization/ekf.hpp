#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "geometry/pose.hpp"

namespace fleet::localization {

/// The state: x, y, theta (map frame), vx, vy (body frame), omega [Forklift thesis, eq. 4.6]; plus,
/// beyond the thesis, the gyro bias b (rad/s). With EkfParams::gyro_bias off, b is held at exactly 0
/// with zero variance and no correlation to the rest, which is the thesis's six-state filter: the extra
/// row and column only ever multiply zeros.
inline constexpr int kStateSize = 7;
using StateVector = Eigen::Matrix<double, kStateSize, 1>;
using StateCovariance = Eigen::Matrix<double, kStateSize, kStateSize>;

enum StateIndex : int { kX = 0, kY = 1, kTheta = 2, kVx = 3, kVy = 4, kOmega = 5, kBias = 6 };

/// A body-frame velocity: from the commands sent to the drive, or from wheel encoders.
struct BodyVelocity {
  double vx = 0.0;     ///< m/s, forward
  double vy = 0.0;     ///< m/s, left
  double omega = 0.0;  ///< rad/s
};

/// Where velocity updates come from (beyond the thesis: its estimate lagged in curves "for want of
/// wheel speeds" [Forklift thesis, section 4.1]).
enum class VelocitySource { kNone, kCommanded, kEncoders };

struct EkfParams {
  /// Antenna offset (a, b) in the body frame [Forklift thesis, eq. 4.12].
  geometry::Vec2 antenna_offset{0.05, 0.0};

  /// R_t diagonal per prediction at `nominal_dt` (at the 70 Hz IMU rate [Forklift thesis, eq. 4.16]). A
  /// prediction over dt uses R_t * dt / nominal_dt, so the filter behaves the same at other rates.
  std::array<double, 6> process_noise{1e-5, 1e-5, 1e-4, 1e-8, 1e-3, 1e-6};
  double nominal_dt = 1.0 / 70.0;

  /// Q_t. The seed's values (Forklift thesis, eq. 4.18) are not legible in the text; with use_fix_covariance the
  /// solver's covariance is used, floored at uwb_std^2, otherwise Q_t = uwb_std^2 I.
  double uwb_std = 0.05;  ///< metres
  bool use_fix_covariance = false;

  /// Sigma_0 of the initialisation (Forklift thesis, eq. 4.14); the thesis gives none. With use_fix_covariance the
  /// first fix's Q_t is added to the position block, so that a fix spoiled by NLOS does not pin
  /// the filter to the wrong place.
  double init_position_std = 0.05;  ///< metres
  /// Fig. 4.3 initialises on the first *valid* fix. With use_fix_covariance, valid means its
  /// largest standard deviation is at most this: a fix whose ranges disagree (NLOS) waits.
  double init_max_fix_std = 0.10;   ///< metres
  double init_heading_std = 0.05;   ///< rad, when the start heading is trusted (seed: always 0)
  double init_velocity_std = 0.05;  ///< m/s and rad/s; the thesis starts at rest
  double initial_heading = 0.0;     ///< rad; the thesis's forklifts always start at heading 0

  // Beyond the thesis, each switchable so its effect can be measured.

  /// 1. Mahalanobis gating of UWB fixes: a fix whose squared innovation distance exceeds
  /// gate_chi2 (chi-square, 2 dof) is rejected. After max_consecutive_rejections in a row the
  /// filter assumes it is the estimate that is wrong, inflates its position covariance and
  /// accepts again, so gating cannot lock the filter out for good.
  bool gating = false;
  double gate_chi2 = 13.8;  ///< 99.9 % for 2 dof
  int max_consecutive_rejections = 10;

  /// 2. Velocity updates from commands or encoders, z = (vx, vy, omega), H = [0 | I3].
  VelocitySource velocity_source = VelocitySource::kNone;
  std::array<double, 3> commanded_velocity_std{0.02, 0.02, 0.10};  ///< m/s, m/s, rad/s
  std::array<double, 3> encoder_velocity_std{0.01, 0.01, 0.05};

  /// 3. Heading initialisation from motion: the first fix sets the position (Forklift thesis, eq. 4.14); the
  /// heading stays unresolved (not corrected, velocity updates withheld) until the robot has
  /// moved heading_init_distance. It is then the rotation that best aligns the dead-reckoned
  /// antenna track (gyro + velocities, in the start frame) with the fixes (2-D Procrustes,
  /// weighted by each fix's Q_t, refitted once without fixes outside their 99.7 % ellipse).
  bool heading_init = false;
  double heading_init_distance = 0.25;  ///< metres of dead-reckoned travel

  /// 4. Gyro bias state. Eq. 4.8 integrates the raw gyro, so any bias becomes a heading drift
  /// that only the UWB fixes (a 5 cm antenna lever arm, and the direction of travel) can pull
  /// back. With this on, theta is predicted with (gyro - b) and b is a random walk with
  /// gyro_bias_random_walk, matching a MEMS gyro's drift; b becomes observable through the heading
  /// corrections of the UWB updates and, at standstill, through update 5.
  bool gyro_bias = false;
  double gyro_bias_random_walk = 2.0e-4;  ///< rad/s per sqrt(s)
  double init_gyro_bias_std = 0.003;      ///< rad/s, residual bias after start-up

  /// 5. Zero-velocity updates. When update_commanded has seen an all-zero command for
  /// standstill_delay seconds (the wheels have stopped), it applies update_standstill() instead
  /// of the commanded-velocity update: (vx, vy, omega) = 0 with standstill_velocity_std, and the
  /// latest gyro reading as a measurement of omega + b with gyro_noise_std. At rest the gyro reads
  /// its bias, so every stop calibrates it. Works whatever velocity_source is.
  bool standstill_update = false;
  double standstill_delay = 0.25;  ///< s of zero command before the wheels count as stopped
  std::array<double, 3> standstill_velocity_std{0.002, 0.002, 0.002};  ///< m/s, m/s, rad/s
  double gyro_noise_std = 0.005;                                       ///< rad/s per reading (white noise of the gyro)

  /// The seed's filter exactly: R_t of eq. 4.16, fixed Q_t, no gating, no velocity updates,
  /// heading 0 at start, no gyro bias state, no zero-velocity updates.
  static EkfParams seed();
  /// Every beyond-thesis feature on, noise tuned to the simulated sensors (see the README).
  static EkfParams tuned();
  /// The picker's filter: wheel odometry (Picker thesis, eq. 3.7) for the velocities and, standing in for a gyro, the
  /// yaw rate; marker sightings for the pose [Picker thesis, section 4.2.9]; started at a known pose, gated.
  static EkfParams picker();
};

/// One marker at a known place on the site, seen by a camera on the body: the measurement of the picker's
/// localization by markers [Picker thesis, section 4.2.9]. The thesis gives no equations; Fleet fuses each sighting
/// as a range and bearing, z = (d, alpha), of a landmark at a known position.
struct MarkerSighting {
  geometry::Vec2 marker;      ///< the marker's position on the site, metres
  geometry::Vec2 camera;      ///< the camera's optical centre in the body frame, metres
  double camera_yaw = 0.0;    ///< the camera's axis in the body frame, rad
  double d = 0.0;             ///< measured distance camera -> marker, metres
  double alpha = 0.0;         ///< measured bearing from the optical axis, rad, positive to the left
  double sigma_d = 0.05;      ///< standard deviation of d, metres
  double sigma_alpha = 0.01;  ///< standard deviation of alpha, rad
};

enum class UpdateStatus {
  kAccepted,           ///< applied to the state
  kGated,              ///< UWB fix rejected by the Mahalanobis gate
  kRejectedNonFinite,  ///< NaN or infinity in the input; nothing changed
  kNotInitialized,     ///< no state yet (velocity before the first fix, or a first fix too
                       ///< uncertain to initialise from)
  kInitialized,        ///< this fix initialised the filter
  kDeferred,           ///< velocity recorded for heading initialisation, state not updated yet
  kIgnored,            ///< the source is switched off in EkfParams
};

/// The forklift's localization filter, the loop of [Forklift thesis, chapter 4, Fig. 4.3]:
///   on a UWB fix:  initialise if needed (Forklift thesis, eq. 4.14),
///                  else update (Forklift thesis, eqs. 4.10-4.13, 4.17, 4.3-4.5);
///   on a gyro reading: predict (Forklift thesis, eqs. 4.8, 4.15, 4.16, 4.1-4.2) and publish the pose.
/// Every input is checked: a NaN or infinity is rejected and leaves the state untouched.
/// Not thread-safe.
class Ekf {
 public:
  /// Throws std::invalid_argument naming the field for a negative noise, a non-positive std or
  /// threshold, or a non-finite value.
  explicit Ekf(const EkfParams& params = EkfParams::tuned());

  /// Prediction with the gyro's yaw rate over dt seconds. Returns false (and changes nothing)
  /// for non-finite input or dt <= 0, and before initialisation except for the heading tracker.
  bool predict(double gyro_omega, double dt);

  /// UWB antenna position fix with its covariance (ignored unless use_fix_covariance).
  UpdateStatus update_uwb(const geometry::Vec2& antenna_position,
                          const Eigen::Matrix2d& covariance = Eigen::Matrix2d::Identity() * 0.0025);

  /// Velocity update from the drive command. No-op unless velocity_source == commanded, except
  /// that with standstill_update a command that has been all zero for standstill_delay seconds
  /// (counted by predict) triggers update_standstill() whatever the velocity source.
  UpdateStatus update_commanded(const BodyVelocity& cmd);
  /// Zero-velocity update for a robot known to stand still (the caller's own standstill
  /// detection, or update_commanded's): (vx, vy, omega) = 0 and, with gyro_bias, the latest gyro
  /// reading as a measurement of omega + b. Ignored unless standstill_update.
  UpdateStatus update_standstill();
  /// Velocity update from wheel encoders (already through forward kinematics). No-op unless
  /// velocity_source == encoders.
  UpdateStatus update_encoders(const BodyVelocity& measured);

  /// Starts the filter at a known pose at rest (a robot at its home), heading resolved.
  void initialize_at(const geometry::Pose2& pose, double position_std, double heading_std);

  /// Marker update: range and bearing of a known marker from a camera on the body, gated like a UWB fix
  /// (section 1 of EkfParams) at the same chi-square threshold.
  UpdateStatus update_marker(const MarkerSighting& z);

  bool initialized() const { return initialized_; }
  /// False while heading initialisation waits for motion: pose().yaw is then a placeholder.
  bool heading_resolved() const { return heading_resolved_; }

  geometry::Pose2 pose() const;
  BodyVelocity velocity() const;
  const StateVector& state() const { return x_; }
  const StateCovariance& covariance() const { return P_; }

  /// Localization quality in [0, 1]: 0 until initialised and while the heading is unresolved
  /// (capped at 0.2); otherwise the product of a covariance term 1 / (1 + (sigma_pos / 5 cm)^2 +
  /// (sigma_theta / 5 deg)^2) and an innovation-consistency term exp(-max(0, NIS - 2) / 4), NIS
  /// being a running mean of UWB normalised innovations squared (2 when the filter is consistent).
  double score() const;

  /// Running mean of the UWB normalised innovation squared.
  double mean_nis() const { return nis_mean_; }
  int consecutive_rejections() const { return consecutive_rejections_; }

  /// Estimated gyro bias, rad/s (0 unless gyro_bias).
  double gyro_bias() const { return x_(kBias); }

  const EkfParams& params() const { return params_; }

  // The models, public so that tests can check the Jacobians against numerical derivatives.
  /// g(u_t, mu_{t-1}) [Forklift thesis, eq. 4.8], with the heading integrating (gyro - b); b = 0 is eq. 4.8.
  static StateVector motion_model(const StateVector& x, double gyro_omega, double dt);
  /// G_t = dg/dx [Forklift thesis, eq. 4.15] (see ekf.cpp for the theta/omega entry), plus d theta / d b.
  static StateCovariance motion_jacobian(const StateVector& x, double dt);
  /// h(mu) [Forklift thesis, eq. 4.13].
  static Eigen::Vector2d measurement_model(const StateVector& x, const geometry::Vec2& offset);
  /// H_t = dh/dx [Forklift thesis, eq. 4.17].
  static Eigen::Matrix<double, 2, kStateSize> measurement_jacobian(const StateVector& x, const geometry::Vec2& offset);
  /// (d, alpha) of a sighting's marker from its camera, for the state x.
  static Eigen::Vector2d marker_model(const StateVector& x, const MarkerSighting& z);
  /// d (d, alpha) / dx.
  static Eigen::Matrix<double, 2, kStateSize> marker_jacobian(const StateVector& x, const MarkerSighting& z);

 private:
  void initialize(const geometry::Vec2& antenna_position, const Eigen::Matrix2d& covariance);
  Eigen::Matrix2d measurement_noise(const Eigen::Matrix2d& fix_covariance) const;
  UpdateStatus update_velocity(const BodyVelocity& z, const std::array<double, 3>& std);
  /// Mahalanobis gate of a 2-D innovation (EkfParams::gating): false to reject it. After
  /// max_consecutive_rejections in a row the position covariance grows by `widening` and it passes.
  /// Sets the innovation covariance `s` and the normalised innovation squared `nis`.
  bool passes_gate(const Eigen::Vector2d& innovation, const Eigen::Matrix<double, 2, kStateSize>& h,
                   const Eigen::Matrix2d& q, const Eigen::Matrix2d& widening, Eigen::Matrix2d& s, double& nis);
  /// Removes every correlation of the state `i` (whose value is a placeholder or a constant).
  void decouple(int i);
  void track_heading(double gyro_omega, double dt);
  void try_resolve_heading();

  EkfParams params_;
  bool initialized_ = false;
  bool heading_resolved_ = false;
  StateVector x_ = StateVector::Zero();
  StateCovariance P_ = StateCovariance::Identity();
  double nis_mean_ = 2.0;
  int consecutive_rejections_ = 0;
  double last_gyro_ = 0.0;  ///< latest gyro reading, for the standstill bias measurement
  bool have_gyro_ = false;
  double zero_command_for_ = 0.0;  ///< s since the command was last non-zero (predict's dt)
  bool command_zero_ = false;

  // Heading initialisation from motion: dead reckoning in the frame of the body at the first fix.
  struct TrackPoint {
    geometry::Vec2 dead_reckoned_antenna;  ///< start-body frame
    geometry::Vec2 fix;                    ///< map frame
    double variance = 0.0;                 ///< per axis, of the fix, m^2
  };
  double dr_yaw_ = 0.0;         ///< rotation since the first fix (gyro)
  geometry::Vec2 dr_position_;  ///< body origin in the start-body frame
  BodyVelocity last_velocity_;  ///< latest velocity measurement
  bool have_velocity_ = false;
  std::vector<TrackPoint> track_;
};

}  // namespace fleet::localization
