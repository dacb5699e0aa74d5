#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "control/attractor_dynamics.hpp"
#include "geometry/pose.hpp"
#include "sim/tricycle.hpp"

namespace fleet::control {

/// An EPAL 1200 x 800 pallet entered on its 800 mm face [Stacker thesis, section 4.1.3]. A pallet pose is its
/// centre with the yaw of its fork-entry axis pointing out of the entry face, so that the docked stacker has the
/// pallet's yaw (its forks, behind it, point into the pallet).
struct PalletGeometry {
  double depth = 1.2;              ///< along the entry axis, metres
  double width = 0.8;              ///< across, metres
  double pocket_spacing = 0.3725;  ///< pocket centre to pocket centre, metres (blocks 100/145/100, pockets 227.5)
  double pocket_width = 0.2275;    ///< metres
};

/// Docking phases: the two-target approach [Stacker thesis, sections 6.3.1-6.3.2], the pivot about the rear axle
/// [Stacker thesis, section 5.2], the final law beyond (kFinalApproach) and inside (kFinalAlign) its threshold distance
/// [Stacker thesis, section 6.3.3], then the forks go in. kRealign is beyond the thesis: when the fork tips arrive at
/// the threshold off the pocket centres, the stacker drives out along the pallet axis and reverses in again.
enum class DockingPhase {
  kToTarget1,
  kReverseToTarget2,
  kPivot,
  kFinalApproach,
  kFinalAlign,
  kRealign,
  kForkIn,
  kDone,
  kFailed,
};

enum class DockingEvent {
  kNearTarget1,          ///< within 0.63 m of target 1 [Stacker thesis, section 6.3.2]
  kTarget2Reached,       ///< within 0.05 m of target 2 [Stacker thesis, section 6.3.2]
  kPivotDone,            ///< rear roughly facing the pallet [Stacker thesis, section 6.3]
  kThresholdAligned,     ///< at the threshold distance with the fork tips on the pockets
  kThresholdMisaligned,  ///< at the threshold distance with the fork tips off the pockets
  kRealigned,            ///< back out at the realignment stand-off
  kAligned,              ///< orientation error below the tolerance [Stacker thesis, section 6.3.3]
  kForksIn,              ///< fork tips at the pocket depth
  kGiveUp,               ///< too many realignments
  kTimeout,              ///< the manoeuvre took longer than its limit (any active phase)
  kBadInput,             ///< a non-finite pose or time step (any active phase)
};

const char* to_string(DockingPhase phase);
const char* to_string(DockingEvent event);

struct DockingTransition {
  DockingPhase from;
  DockingEvent event;
  DockingPhase to;
};

/// The rows, in the order they are matched. kTimeout and kBadInput lead from every phase but kDone and kFailed to
/// kFailed by a rule outside the table.
std::span<const DockingTransition> docking_transition_table();
/// The phase `event` leads to from `from`, or nothing when the event does not apply there.
std::optional<DockingPhase> next_docking_phase(DockingPhase from, DockingEvent event);

/// Settings of one docking law instance. The thesis gives the stand-offs, the switching distances and the final
/// speed; everything marked "chosen" it leaves open.
struct DockingParams {
  PalletGeometry pallet;
  sim::TricycleGeometry vehicle;
  AttractorParams attractor;

  // Targets [Stacker thesis, eq. 6.1-6.2, sections 6.3.1-6.3.2].
  double target2_standoff = 0.7;          ///< rear axle from the pallet face at target 2 (1.3 m from its centre), m
  double target1_offset = 1.5;            ///< target 1 along the pallet row from target 2, m
  double target1_extra_standoff = 0.5;    ///< target 1 further from the face than target 2, m (chosen)
  double target1_switch_distance = 0.63;  ///< reverse once this close to target 1, m
  double target2_tolerance = 0.05;        ///< m
  double approach_speed = 0.5;            ///< v_des forwards to target 1, m/s (chosen)
  double reverse_speed = 0.3;             ///< v_des backwards to target 2, m/s (chosen)
  double arrival_gain = 0.8;              ///< v_des <= gain * distance near a target, 1/s (chosen, beyond the thesis)
  double min_arrival_speed = 0.04;        ///< m/s (chosen)

  // Pivot [Stacker thesis, section 5.2]: theta_steer = +-pi/2.
  double pivot_gain = 1.2;               ///< yaw rate per rad of orientation error, 1/s (chosen)
  double max_pivot_wheel_speed = 0.35;   ///< m/s (chosen)
  double pivot_tolerance = 0.0175;       ///< rad (1 deg; the thesis's threshold is not given)
  double steer_settle_tolerance = 0.05;  ///< the wheel waits for the steering this close before rolling, rad

  // Final law [Stacker thesis, eq. 6.3-6.5, section 6.3.3].
  double final_speed = 0.25;          ///< |v| beyond the threshold, m/s [Stacker thesis, section 6.3.3]
  double final_slow_speed = 0.08;     ///< |v| just before the threshold, m/s (chosen)
  double final_slow_distance = 0.15;  ///< m (chosen)
  double k1 = 1.5;                    ///< eq. 6.4, m/s per rad (chosen)
  double k2 = 16.0;                   ///< eq. 6.5, rad per rad (chosen: critically damps the lateral error)
  double lookahead = 0.3;             ///< sigma aims the rear at the pallet axis this far ahead, m (beyond the thesis)
  double max_final_steer = 1.1;       ///< |theta_steer| while reversing in, rad (chosen)
  double threshold_standoff = 0.25;   ///< rear axle from the pallet face at the threshold, m (chosen)
  double align_tolerance = 0.0026;    ///< rad (0.15 deg; the thesis stops at 1.0 deg)
  int align_confirmations = 3;        ///< consecutive periods below the tolerance
  double lateral_tolerance = 0.010;   ///< fork tips off the pocket centres at the threshold, m (beyond the thesis)
  double entry_yaw_tolerance = 0.05;  ///< rad, at the threshold (beyond the thesis)

  // Realignment (beyond the thesis).
  double realign_standoff = 1.2;  ///< rear axle from the face; the front stays 0.18 m inside a 2.98 m corridor, m
  double realign_speed = 0.2;     ///< m/s
  int max_realignments = 3;

  // Fork in.
  double fork_in_speed = 0.2;  ///< m/s (chosen)
  double pocket_depth = 1.10;  ///< fork tips beyond the pallet face when docked, m (chosen: 0.1 m short of the back)
  double yaw_hold_gain = 1.5;  ///< 1/s (chosen)
  double max_fork_in_steer = 0.2;  ///< rad

  // Pallet estimate.
  /// Beyond the thesis: the largest heading error of the law's frame that detections' yaws correct the logistics
  /// position for; a larger offset is a pallet standing askew, rad.
  double max_heading_correction = 0.1;
  int heading_samples = 5;      ///< detections averaged for the heading before the first is accepted
  double detection_gate = 0.7;  ///< first detection within this of the expected pallet (the thesis's docking area), m
  double outlier_gate = 0.15;   ///< later detections within this of the running mean, m
  double time_limit = 240.0;    ///< s
  /// Putting a carried pallet down (beyond the thesis, which only picks): the prior is the place
  /// it goes to, there is nothing to detect, and the law docks the carried pallet onto the prior.
  bool place_on_prior = false;
};

/// What the law reads each control period.
struct DockingInput {
  geometry::Pose2 vehicle;                          ///< estimated pose of the rear-axle midpoint
  double steer_angle = 0.0;                         ///< measured steering angle, rad
  std::optional<geometry::Pose2> pallet_detection;  ///< this period's detection (centre + entry-axis yaw), if any
  std::span<const geometry::Vec2> obstacles;        ///< lidar points in the vehicle frame, for the approach legs
  double dt = 0.05;                                 ///< s
};

struct DockingOutput {
  sim::TricycleCommand command;
  DockingPhase phase = DockingPhase::kToTarget1;
  std::optional<DockingEvent> event;  ///< fired during this update
  std::string failure_reason;
  geometry::Pose2 pallet_estimate;
  geometry::Vec2 target1;
  geometry::Vec2 target2;
  double lateral_error = 0.0;  ///< fork-tip midpoint off the pallet axis, m
  double yaw_error = 0.0;      ///< vehicle yaw minus pallet yaw, rad
  double final_error = 0.0;    ///< e of eq. 6.3 (kFinalApproach, kFinalAlign), rad
};

/// The stacker's docking law. One instance per docking; not thread-safe.
class DockingLaw {
 public:
  /// `pallet_prior` is the pallet pose the job gave (the thesis's logistics position); `start` picks the side of
  /// target 1. Throws std::invalid_argument for a non-finite prior or start.
  DockingLaw(const DockingParams& params, const geometry::Pose2& pallet_prior, const geometry::Pose2& start,
             std::uint64_t seed = 0);

  DockingOutput update(const DockingInput& input);

  DockingPhase phase() const { return phase_; }
  /// The pallet pose the law steers by: the mean of the accepted detections, or the prior before the first.
  geometry::Pose2 pallet_estimate() const;
  /// Where the rear axle is steered to before the final approach: targets 1 and 2 [Stacker thesis, eq. 6.1-6.2],
  /// from the current pallet estimate.
  std::array<geometry::Vec2, 2> targets() const;
  int realignments() const { return realignments_; }
  int accepted_detections() const { return detections_; }
  const DockingParams& params() const { return params_; }

 private:
  struct AxisFrame;  // the vehicle seen from the pallet's entry axis

  void correct_prior_heading(const geometry::Pose2& detection);
  void accept_detection(const geometry::Pose2& detection);
  void fire(DockingEvent event, DockingOutput& out);
  AxisFrame axis_frame(const geometry::Pose2& vehicle) const;
  /// Zero speed until the wheel has turned to `theta` once in this phase.
  double after_steering_settles(double theta, double measured, double v);

  sim::TricycleCommand to_target1(const DockingInput& in, DockingOutput& out);
  sim::TricycleCommand reverse_to_target2(const DockingInput& in, DockingOutput& out);
  sim::TricycleCommand pivot(const DockingInput& in, DockingOutput& out);
  sim::TricycleCommand final_approach(const DockingInput& in, DockingOutput& out);
  sim::TricycleCommand final_align(const DockingInput& in, DockingOutput& out);
  sim::TricycleCommand realign(const DockingInput& in, DockingOutput& out);
  sim::TricycleCommand fork_in(const DockingInput& in, DockingOutput& out);

  DockingParams params_;
  geometry::Pose2 prior_;            ///< the logistics position, turned by the heading the detections measure
  geometry::Pose2 logistics_prior_;  ///< as the job gave it
  geometry::Pose2 start_;
  double heading_offsets_ = 0.0;
  int heading_samples_ = 0;
  AttractorNavigator navigator_;
  DockingPhase phase_ = DockingPhase::kToTarget1;
  double side_ = 1.0;  ///< target 1 lies on this side of target 2 along the pallet row
  double elapsed_ = 0.0;
  bool steer_settled_ = false;
  double turn_sign_ = 1.0;  ///< steering side of the pivot and of the in-place alignment
  int confirmations_ = 0;
  int realignments_ = 0;
  // Running mean of the accepted detections.
  int detections_ = 0;
  double sum_x_ = 0.0;
  double sum_y_ = 0.0;
  double sum_cos_ = 0.0;
  double sum_sin_ = 0.0;
  std::string failure_;
};

}  // namespace fleet::control
