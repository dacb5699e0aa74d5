#pragma once

#include "control/forklift_geometry.hpp"
#include "control/pallet_pick.hpp"
#include "control/twist.hpp"
#include "geometry/pose.hpp"

namespace fleet::control {

/// Settings of the placing controller [Forklift thesis, section 6.3, eq. 6.5].
struct PlaceParams {
  double a = 1.5;                   ///< heading gain, 1/s (Forklift thesis, eq. 6.5: omega = -a d_h)
  double b = 1.5;                   ///< lateral gain, 1/s (Forklift thesis, eq. 6.5: v_y = -b d_x)
  double c = 1.2;                   ///< longitudinal gain, 1/s (Forklift thesis, eq. 6.5: v_x = -c d_y)
  double heading_tol = 0.012;       ///< rad
  double lateral_tol = 0.003;       ///< m
  double longitudinal_tol = 0.003;  ///< m
  /// An earlier error that grows past this multiple of its tolerance sends the controller back
  /// to that stage (the order of eq. 6.5 holds only while the earlier errors stay zero).
  double reenter_factor = 3.0;
  double omega_limit = 0.5;   ///< rad/s
  double vy_limit = 0.05;     ///< m/s
  double vx_limit = 0.08;     ///< m/s
  double omega_floor = 0.03;  ///< smallest turn the motors still follow, rad/s
  double v_floor = 0.006;     ///< smallest translation the motors still follow, m/s
  /// Inside all tolerances, stand still this long before lowering and check again: at rest the
  /// localization averages many more UWB fixes than it can while moving, so the check after the
  /// pause is made on a better estimate, and a remaining error is corrected first.
  double settle_time = 1.0;         ///< s; 0 lowers at once (the thesis's behaviour)
  int max_settles = 3;              ///< then lower whatever the last check said
  double lower_time = 1.0;          ///< time to lower the forks, s
  double back_out_distance = 0.15;  ///< reverse this far after lowering, m
  double back_out_speed = 0.06;     ///< m/s
  double timeout = 60.0;            ///< whole place, s
};

enum class PlaceStatus { kIdle, kHeading, kLateral, kLongitudinal, kSettling, kLowering, kBackingOut, kDone, kFailed };
const char* to_string(PlaceStatus status);

/// Places the carried pallet on a loading area using the localization estimate
/// [Forklift thesis, section 6.3]: the heading error, then the lateral error, then the longitudinal error are
/// driven to zero one after another (Forklift thesis, eq. 6.5), so that the forklift faces the area and then
/// drives straight into it without sweeping over its neighbours. Then lowers and backs out.
class PalletPlace {
 public:
  explicit PalletPlace(PlaceParams params = {}, ForkliftGeometry geometry = {});

  /// The robot pose that puts a carried pallet (seated at carry_x) onto the area's pose.
  static geometry::Pose2 place_pose(const geometry::Pose2& area, double carry_x);

  void start(const geometry::Pose2& area, double t);
  void stop();

  ForkCommand step(double t, const geometry::Pose2& pose, double dt);

  PlaceStatus status() const { return status_; }
  bool done() const { return status_ == PlaceStatus::kDone || status_ == PlaceStatus::kFailed; }
  const geometry::Pose2& target() const { return target_; }

 private:
  PlaceParams params_;
  ForkliftGeometry geometry_;
  PlaceStatus status_ = PlaceStatus::kIdle;
  geometry::Pose2 target_;
  double start_time_ = 0.0;
  double phase_start_ = 0.0;
  double back_left_ = 0.0;
  int settles_ = 0;
};

}  // namespace fleet::control
