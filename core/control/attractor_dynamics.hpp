#pragma once

#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include "geometry/pose.hpp"
#include "sim/tricycle.hpp"

namespace fleet::control {

/// Gains of the attractor dynamics [Stacker thesis, eq. 3.3-3.18]. The thesis gives none of them; these respect the
/// ordering of eq. 3.18 (lambda_tar << c_v_tar, lambda_obs << c_v_obs, lambda_tar << lambda_obs) with
/// lambda_obs <= beta1.
struct AttractorParams {
  // Heading [Stacker thesis, eq. 3.4-3.11].
  double lambda_tar = 0.8;         ///< attraction strength to the target, 1/s
  double beta1 = 4.0;              ///< largest repulsion strength, 1/s [Stacker thesis, eq. 3.6]
  double beta2 = 0.6;              ///< decay length of the repulsion with the clearance, m [Stacker thesis, eq. 3.6]
  double robot_half_width = 0.48;  ///< B of eq. 3.7: half the chassis width plus 0.10 m margin, m
  double noise_variance = 0.0;     ///< Q of eq. 3.10, rad^2/s^2 (0: no stochastic force)
  double max_heading_rate = 0.9;   ///< |phi'| handed to the wheel, rad/s
  // Virtual sensors [Stacker thesis, section 6.1.2]: 41 sectors of 8.78 deg round the reference point, the 21 frontal
  // ones used.
  int sector_count = 41;
  int used_sectors = 21;
  double sensor_range = 3.0;  ///< clearances beyond this are ignored (sdistance_max of Algorithms 2-3), m
  // Speed [Stacker thesis, eq. 3.12-3.17].
  double c = 20.0;               ///< gain of the threshold function alpha = atan(c U)/pi [Stacker thesis, eq. 3.15]
  double c_v_obs = 12.0;         ///< 1/s [Stacker thesis, eq. 3.16]
  double c_v_tar = 6.0;          ///< 1/s [Stacker thesis, eq. 3.17]
  double time_to_contact = 2.0;  ///< T_obs of eq. 3.13, s
  double desired_speed = 0.5;    ///< v_des, m/s, when the goal does not say
};

/// Where to go. `direction` is +1 forwards or -1 backwards (dir of Algorithms 1 and 3).
struct AttractorGoal {
  geometry::Vec2 target;
  int direction = 1;
  double desired_speed = -1.0;  ///< v_des, m/s; negative takes AttractorParams::desired_speed
};

/// One frontal virtual sensor: its direction relative to the direction of travel and the obstacle's clearance
/// from the stacker's outline along it (+inf when it sees nothing).
struct Sector {
  double bearing = 0.0;    ///< theta_i, rad
  double clearance = 0.0;  ///< d_i, m
  double reach = 0.0;      ///< outline distance from the reference point along the bearing, m
};

/// Everything one update computed, for logs, plots and tests.
struct AttractorOutput {
  double heading = 0.0;        ///< phi: direction of travel (yaw, or yaw + pi backwards), rad
  double psi_tar = 0.0;        ///< [Stacker thesis, eq. 3.3]
  double f_tar = 0.0;          ///< [Stacker thesis, eq. 3.4]
  double f_obs = 0.0;          ///< [Stacker thesis, eq. 3.8]
  double f_stoch = 0.0;        ///< [Stacker thesis, eq. 3.10]
  double heading_rate = 0.0;   ///< F_t, clamped to max_heading_rate [Stacker thesis, eq. 3.11, Algorithm 3]
  double potential = 0.0;      ///< U [Stacker thesis, eq. 3.14]
  double alpha = 0.0;          ///< [Stacker thesis, eq. 3.15]
  double min_clearance = 0.0;  ///< d_min, m (+inf without obstacles)
  double v_obs = 0.0;          ///< [Stacker thesis, eq. 3.13]
  double speed = 0.0;          ///< v after this update (unsigned), m/s
  double target_distance = 0.0;
  sim::TricycleCommand command;  ///< for the drive-steering wheel [Stacker thesis, Algorithm 3]
};

/// The 21 frontal virtual sensors of [Stacker thesis, section 6.1.2] from obstacle points given in the vehicle
/// frame (origin at the rear-axle midpoint, as the two S300 scans are after eq. 5.19-5.20). `travel_bearing` is 0
/// when driving forwards and pi backwards: the sectors look where the stacker goes. A sector's clearance is the
/// smallest distance of its points from the reference point minus the outline's reach along the sector centre, so
/// that a wall beside the chassis and one ahead of the bumper count the same way.
std::vector<Sector> frontal_sectors(std::span<const geometry::Vec2> points, double travel_bearing,
                                    const sim::TricycleGeometry& geometry, const AttractorParams& params);

/// [Stacker thesis, eq. 3.4]: -lambda_tar sin(phi - psi_tar).
double target_force(double phi, double psi_tar, double lambda_tar);

/// Repulsion, potential and d_min of a set of sectors [Stacker thesis, eq. 3.5-3.8, 3.14]. Eq. 3.5 is printed with a
/// double negative in the exponent; the Gaussian decays, exp(-(phi - psi_i)^2 / (2 sigma_i^2)).
struct ObstacleField {
  double force = 0.0;
  double potential = 0.0;
  double min_clearance = 0.0;
};
ObstacleField obstacle_field(std::span<const Sector> sectors, const AttractorParams& params);

/// alpha = atan(c U) / pi in (-1/2, 1/2) [Stacker thesis, eq. 3.15]; the print's atan(c U / pi) would not span the
/// stated range.
double speed_threshold(double potential, double c);

/// The merged heading and speed dynamics of [Stacker thesis, Algorithm 3] mapped onto the drive-steering wheel by
/// the inverse kinematics [Stacker thesis, eq. 5.17]. It keeps the speed v as its state: Algorithm 3 writes g (= v')
/// where v belongs; here v' is integrated (exactly over dt, the dynamics being linear in v for a held U).
///
/// Not thread-safe: one owner updates it.
class AttractorNavigator {
 public:
  /// `seed` drives the stochastic force only (used when noise_variance > 0).
  AttractorNavigator(const AttractorParams& params, const sim::TricycleGeometry& geometry, std::uint64_t seed = 0);

  /// One control period: `pose` is the estimated pose of the rear-axle midpoint, `obstacles` are points in the
  /// vehicle frame. Returns the wheel command with everything it was made of.
  AttractorOutput update(const geometry::Pose2& pose, const AttractorGoal& goal,
                         std::span<const geometry::Vec2> obstacles, double dt);

  /// Sets the speed state, e.g. to the desired speed when a leg starts while the stacker is already rolling.
  void reset_speed(double v) { speed_ = v; }
  double speed() const { return speed_; }
  const AttractorParams& params() const { return params_; }

 private:
  AttractorParams params_;
  sim::TricycleGeometry geometry_;
  std::mt19937_64 rng_;
  double speed_ = 0.0;
};

}  // namespace fleet::control
