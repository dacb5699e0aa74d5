#pragma once

#include <cstdint>
#include <optional>
#include <random>
#include <span>
#include <vector>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "localization/ekf.hpp"
#include "perception/marker_camera.hpp"
#include "sim/encoders.hpp"
#include "sim/imu.hpp"
#include "sim/mecanum.hpp"
#include "sim/summit_xls.hpp"

namespace fleet::localization {

struct MarkerLocalizerParams {
  /// The front-right camera; the rear-left one is its mirror [Picker thesis, section 3.1.1].
  perception::MarkerCameraParams camera = perception::MarkerCameraParams::axis_ptz();
  sim::EncoderParams encoders = sim::summit_xls_encoder_params();
  EkfParams ekf = EkfParams::picker();
  /// Sightings fused per camera per second: a marker's systematic error repeats in every frame, so fusing all
  /// 30 would make the filter sure of it.
  double fuse_rate_hz = 5.0;
  /// Beyond the thesis, whose robot localises from markers and wheel odometry alone: a MEMS yaw-rate
  /// gyro drives the prediction. The rollers of a mecanum wheel slip, and the wheels' yaw rate turns
  /// the heading estimate away from the truth by degrees a second at 1 m/s, faster than markers 10 m
  /// apart in the open can bring it back. Without one (nullopt) the wheels' yaw rate stands in.
  std::optional<sim::GyroParams> gyro = sim::GyroParams{};
};

/// The picker's localization [Picker thesis, section 4.2.9] as its software runs it: wheel encoders into odometry
/// (Picker thesis, eq. 3.7), the two Axis PTZ cameras aimed at the nearest marker they can decode, and the EKF fusing
/// both (EkfParams::picker, Ekf::update_marker). The cameras and encoders are simulated from the body's truth.
/// Not thread-safe: one owner steps it.
class MarkerLocalizer {
 public:
  /// Throws std::invalid_argument for a non-positive fuse rate.
  MarkerLocalizer(const MarkerLocalizerParams& params, const sim::MecanumParams& base, const geometry::Pose2& start,
                  std::vector<perception::Marker> markers, std::vector<geometry::Polygon> occluders,
                  std::mt19937_64 rng);

  /// One step of `dt` s ending at sim time `t`: the robot commanded `command`, the wheels turned at `wheels`
  /// (truth), the body stands at `truth` moving at `speed` m/s over the floor and turning at `yaw_rate` rad/s.
  /// After the ekf's standstill_delay of zero commands the wheels have stopped: a zero-velocity update, with
  /// the gyro's reading at rest as a measurement of its bias, replaces the encoders' velocities.
  void step(double t, double dt, const sim::BodyTwist& command, const sim::WheelSpeeds& wheels,
            const geometry::Pose2& truth, double speed, double yaw_rate);

  const Ekf& ekf() const { return ekf_; }
  /// Wheel odometry alone, from the same start: what the robot would know without markers.
  const geometry::Pose2& odometry() const { return odometry_.pose(); }
  int sightings() const { return sightings_; }
  int fused() const { return fused_; }
  int gated() const { return gated_; }
  /// Sim time of the last sighting the filter accepted (the start until one is).
  double last_fused() const { return last_fused_; }
  /// Longest time between two accepted sightings so far.
  double longest_gap() const { return longest_gap_; }
  /// Distinct markers seen.
  const std::vector<int>& markers_seen() const { return seen_; }

 private:
  MarkerLocalizerParams params_;
  std::vector<perception::Marker> markers_;
  sim::WheelEncoders encoders_;
  sim::WheelOdometry odometry_;
  std::optional<sim::Gyro> gyro_;
  std::vector<perception::MarkerCamera> cameras_;
  std::vector<double> next_fusion_;
  double still_for_ = 0.0;  ///< s of zero commands
  Ekf ekf_;
  int sightings_ = 0;
  int fused_ = 0;
  int gated_ = 0;
  double last_fused_ = 0.0;
  double longest_gap_ = 0.0;
  std::vector<int> seen_;
};

}  // namespace fleet::localization
