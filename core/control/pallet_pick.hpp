#pragma once

#include <span>

#include "control/forklift_geometry.hpp"
#include "control/twist.hpp"
#include "perception/marker_camera.hpp"

namespace fleet::control {

/// Settings of the visual-servoing pick [Forklift thesis, section 6.2, eq. 6.4, Fig. 6.7].
struct PickParams {
  double v_minx = 0.03;          ///< constant forward/backward speed while servoing, m/s
  double v_miny = 0.02;          ///< constant sideways speed while servoing, m/s
  double omega_min = 0.10;       ///< turning speed at |gamma| = gamma_min, rad/s
  double omega_limit = 0.40;     ///< cap on eq. 6.4's proportional omega for large gamma, rad/s
  double alpha_min = 0.015;      ///< bearing tolerance, rad
  double gamma_min = 0.025;      ///< relative-yaw tolerance, rad: the pallet's yaw on the forks
  double d_min = 0.15;           ///< stand-off where the marker is still decodable (seed: 15 cm), m
  double d_tol = 0.01;           ///< stand-off tolerance, m
  int settle_frames = 3;         ///< consecutive frames inside all tolerances before driving in
  double drive_in_speed = 0.05;  ///< blind straight drive under the pallet, m/s
  double lift_time = 1.0;        ///< time to raise the forks, s
  double hold_time = 0.15;       ///< keep the last command this long without a new frame, s
  double lost_timeout = 1.5;     ///< no frame of the marker this long while aligning: failed, s
  double timeout = 60.0;         ///< whole pick, s
};

enum class PickStatus { kIdle, kAligning, kDrivingIn, kLifting, kDone, kFailed };
const char* to_string(PickStatus status);

struct ForkCommand {
  BodyTwist twist;
  bool fork_up = false;  ///< forks raised (carrying) or lowered
};

/// Picks the pallet whose marker was found by the search. Aligns on camera input only (visual
/// servoing): first the bearing alpha, then the relative yaw gamma, then the distance to d_min,
/// each with the constant speeds of eq. 6.4; once all hold, drives straight in blind (the marker
/// is too close to decode there) and lifts.
class PalletPick {
 public:
  explicit PalletPick(PickParams params = {}, ForkliftGeometry geometry = {});

  void start(int marker_id, double t);
  void stop();

  /// One step at sim time `t`; `detections` are those of frames taken since the last step (empty
  /// between frames: the last command is held for `hold_time`).
  ForkCommand step(double t, std::span<const perception::MarkerDetection> detections, double dt);

  PickStatus status() const { return status_; }
  bool done() const { return status_ == PickStatus::kDone || status_ == PickStatus::kFailed; }
  const char* failure() const { return failure_; }

  /// Fig. 6.7's decision for one detection: the command the thesis's algorithm gives, and whether
  /// all three errors are inside their tolerances (the "drive towards pallet" branch).
  static BodyTwist servo_command(const perception::MarkerDetection& det, const PickParams& p, bool& aligned);

 private:
  PickParams params_;
  ForkliftGeometry geometry_;
  PickStatus status_ = PickStatus::kIdle;
  int marker_id_ = -1;
  double start_time_ = 0.0;
  double last_seen_ = 0.0;
  double phase_start_ = 0.0;
  int settled_ = 0;
  double d_sum_ = 0.0;
  double drive_left_ = 0.0;
  BodyTwist held_;
  const char* failure_ = "";
};

}  // namespace fleet::control
