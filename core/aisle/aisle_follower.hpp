#pragma once

#include <numbers>
#include <string_view>

#include "aisle/hough_lines.hpp"
#include "sim/mecanum.hpp"

namespace fleet::aisle {

/// The rack face a picker keeps its distance from, seen from the base looking along the aisle. Two pickers share an
/// aisle by following opposite faces [Picker thesis, section 4.3.3.1].
enum class RackSide { kLeft, kRight };

std::string_view to_string(RackSide side);

/// The aisle follower's parameters. The seed gives λ = 5, τ = 0.02 s and k = 1 (Picker thesis, section 4.3.3.4), the
/// rack width and d_ref (Picker thesis, Tables 7-9); it leaves u0, v0 and r0 open ("below the maxima").
struct AisleFollowerParams {
  RackSide side = RackSide::kRight;
  double reference_distance = 1.0;                    ///< d_ref: base centre to the chosen face, metres
                                                      ///< [Picker thesis, Tables 7-9]
  double rack_width = 3.0;                            ///< w_R of eq. 4.33 and of the validity limit on e_y, metres
  double max_heading_error = std::numbers::pi / 3.0;  ///< validity limit on e_θ
                                                      ///< [Picker thesis, hyp e_θ, section 4.3.3.4]
  double forward_speed = 0.3;  ///< u0, m/s: the test speed [Picker thesis, section 3.1] and the seed's forward peak
                               ///< (Picker thesis, Fig. 4.55)
  double lateral_speed = 0.3;  ///< v0, m/s
  double yaw_rate = 0.6;       ///< r0, rad/s
  double lambda_x = 5.0;       ///< sigmoid slopes [Picker thesis, eq. 4.33-4.35], "5 after various trials"
  double lambda_y = 5.0;
  double lambda_theta = 5.0;
  double tau_u = 0.02;  ///< first-order filter time constants [Picker thesis, eq. 4.26-4.29], seconds
  double tau_v = 0.02;
  double tau_r = 0.02;
};

/// Why the errors of a frame can or cannot drive the base.
enum class AisleErrorStatus {
  kValid,
  kNoRackLines,     ///< the frame gave no line pair
  kHeadingOutside,  ///< |e_θ| beyond the validity limit
  kLateralOutside,  ///< |e_y| beyond w_R / cos(e_θ)
};

std::string_view to_string(AisleErrorStatus status);

/// The errors of [Picker thesis, eq. 4.24] in the body frame.
struct AisleErrors {
  AisleErrorStatus status = AisleErrorStatus::kNoRackLines;
  double along = 0.0;          ///< e_x = X_A − X_R: metres still to go along the aisle
  double lateral = 0.0;        ///< e_y: metres to move along body y (positive left) to sit at d_ref
  double heading = 0.0;        ///< e_θ = θ_line − θ_ref: the aisle's direction in the body frame, rad (θ_ref = 0)
  double side_distance = 0.0;  ///< measured base centre to the chosen face, metres

  bool valid() const { return status == AisleErrorStatus::kValid; }
};

/// [Picker thesis, eq. 4.24] from one frame's pair and the distance still to go (which the lines cannot give).
AisleErrors aisle_errors(const RackLinePair& pair, double distance_to_go, const AisleFollowerParams& params);

/// sig(z) = (1 − e^(−λz)) / (1 + e^(−λz)) of [Picker thesis, eq. 4.30-4.35], in (−1, 1).
double sigmoid(double z, double lambda);

/// The aisle-following control of [Picker thesis, eq. 4.33-4.35]: a body twist that turns the base parallel to the
/// racks, brings it to d_ref from the chosen face and drives it the requested distance along the aisle, each axis
/// through its sigmoid and first-order filter. The distance travelled comes from wheel odometry projected on the
/// aisle by the measured heading. One owner steps it.
class AisleFollower {
 public:
  explicit AisleFollower(const AisleFollowerParams& params = {});

  /// Starts a run `distance` metres along the aisle (to point B, from the global planner), from rest.
  void start(double distance);

  /// One control period of `dt` seconds: `pair` is this frame's rack lines, `odometry` the body twist the wheel
  /// encoders measured over the period. Frames without valid errors bring the targets to zero, so the base stops
  /// through its filters rather than driving on blind.
  sim::BodyTwist update(const RackLinePair& pair, const sim::BodyTwist& odometry, double dt);

  const AisleErrors& errors() const { return errors_; }
  const sim::BodyTwist& command() const { return command_; }
  double travelled() const { return travelled_; }
  double distance_to_go() const { return distance_ - travelled_; }
  const AisleFollowerParams& params() const { return params_; }

 private:
  AisleFollowerParams params_;
  AisleErrors errors_;
  sim::BodyTwist command_;
  double distance_ = 0.0;
  double travelled_ = 0.0;
  double heading_ = 0.0;  ///< the last valid e_θ, projects odometry on the aisle
};

}  // namespace fleet::aisle
