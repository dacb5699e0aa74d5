#include "control/attractor_dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace fleet::control {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Distance from the reference point to the stacker's outline along `bearing` (body frame). The outline is the
/// bounding rectangle from the fork tips to the front bumper: a little wider than the forks, so a clearance
/// behind the stacker errs on the safe side.
double outline_reach(double bearing, const sim::TricycleGeometry& g) {
  const double c = std::cos(bearing);
  const double s = std::sin(bearing);
  double reach = kInf;
  if (c > 1e-12) reach = std::min(reach, g.front_x() / c);
  if (c < -1e-12) reach = std::min(reach, g.fork_tip_x() / c);
  if (std::abs(s) > 1e-12) reach = std::min(reach, 0.5 * g.width / std::abs(s));
  return reach;
}

}  // namespace

std::vector<Sector> frontal_sectors(std::span<const geometry::Vec2> points, double travel_bearing,
                                    const sim::TricycleGeometry& geometry, const AttractorParams& params) {
  const double width = 2.0 * std::numbers::pi / params.sector_count;  // 8.78 deg for 41 sectors
  const int half = params.used_sectors / 2;
  std::vector<Sector> sectors(static_cast<std::size_t>(2 * half + 1));
  for (int k = -half; k <= half; ++k) {
    Sector& s = sectors[static_cast<std::size_t>(k + half)];
    s.bearing = k * width;
    s.reach = outline_reach(travel_bearing + s.bearing, geometry);
    s.clearance = kInf;
  }
  for (const geometry::Vec2& p : points) {
    const double range = geometry::norm(p);
    if (!std::isfinite(range) || range <= 0.0) continue;
    const double bearing = std::atan2(p.y, p.x);
    const double relative = geometry::angle_diff(bearing, travel_bearing);
    const int k = static_cast<int>(std::lround(relative / width));
    if (k < -half || k > half) continue;
    Sector& s = sectors[static_cast<std::size_t>(k + half)];
    s.clearance = std::min(s.clearance, std::max(0.0, range - outline_reach(bearing, geometry)));
  }
  return sectors;
}

double target_force(double phi, double psi_tar, double lambda_tar) {
  return -lambda_tar * std::sin(phi - psi_tar);
}

ObstacleField obstacle_field(std::span<const Sector> sectors, const AttractorParams& params) {
  ObstacleField field;
  field.min_clearance = kInf;
  const double half_sector = std::numbers::pi / params.sector_count;  // delta theta / 2
  const double inv_sqrt_e = std::exp(-0.5);
  for (const Sector& s : sectors) {
    if (!(s.clearance <= params.sensor_range)) continue;
    field.min_clearance = std::min(field.min_clearance, s.clearance);
    const double lambda = params.beta1 * std::exp(-s.clearance / params.beta2);  // [Stacker thesis, eq. 3.6]
    // [Stacker thesis, eq. 3.7]: the thesis's L + d_i is the distance from the reference point to the obstacle.
    const double sigma = std::atan(std::tan(half_sector) + params.robot_half_width / (s.reach + s.clearance));
    const double offset = -s.bearing;  // phi - psi_i, with psi_i = phi + theta_i
    const double gauss = std::exp(-offset * offset / (2.0 * sigma * sigma));
    // [Stacker thesis, eq. 3.5, 3.8]
    field.force += lambda * offset * gauss;
    // [Stacker thesis, eq. 3.14]
    field.potential += lambda * sigma * sigma * gauss - lambda * sigma * sigma * inv_sqrt_e;
  }
  return field;
}

double speed_threshold(double potential, double c) {
  return std::atan(c * potential) / std::numbers::pi;
}

AttractorNavigator::AttractorNavigator(const AttractorParams& params, const sim::TricycleGeometry& geometry,
                                       std::uint64_t seed)
    : params_(params), geometry_(geometry), rng_(seed) {
  if (!(params_.lambda_tar > 0.0) || !(params_.beta1 >= 0.0) || !(params_.beta2 > 0.0) ||
      !(params_.noise_variance >= 0.0) || !(params_.max_heading_rate > 0.0) || params_.sector_count < 3 ||
      params_.used_sectors < 1 || params_.used_sectors > params_.sector_count || !(params_.c_v_obs > 0.0) ||
      !(params_.c_v_tar > 0.0) || !(params_.time_to_contact > 0.0) || !(params_.sensor_range > 0.0)) {
    throw std::invalid_argument(
        "AttractorParams: gains, rates, ranges and time_to_contact must be > 0, "
        "noise_variance >= 0, 1 <= used_sectors <= sector_count");
  }
}

AttractorOutput AttractorNavigator::update(const geometry::Pose2& pose, const AttractorGoal& goal,
                                           std::span<const geometry::Vec2> obstacles, double dt) {
  AttractorOutput out;
  const int dir = goal.direction < 0 ? -1 : 1;
  const double v_des = goal.desired_speed >= 0.0 ? goal.desired_speed : params_.desired_speed;
  // Backwards, the planning variable is the direction the rear travels in.
  out.heading = geometry::normalize_angle(pose.yaw + (dir < 0 ? std::numbers::pi : 0.0));
  const geometry::Vec2 to_target = goal.target - pose.position();
  out.target_distance = geometry::norm(to_target);
  out.psi_tar = std::atan2(to_target.y, to_target.x);                      // [Stacker thesis, eq. 3.3]
  out.f_tar = target_force(out.heading, out.psi_tar, params_.lambda_tar);  // [Stacker thesis, eq. 3.4]
  const std::vector<Sector> sectors = frontal_sectors(obstacles, dir < 0 ? std::numbers::pi : 0.0, geometry_, params_);
  const ObstacleField field = obstacle_field(sectors, params_);
  out.f_obs = field.force;
  if (params_.noise_variance > 0.0) {
    // [Stacker thesis, eq. 3.10]
    out.f_stoch = std::sqrt(params_.noise_variance) * std::normal_distribution<double>(0.0, 1.0)(rng_);
  }
  out.heading_rate = std::clamp(out.f_obs + out.f_tar + out.f_stoch, -params_.max_heading_rate,
                                params_.max_heading_rate);  // [Stacker thesis, eq. 3.11]

  // Speed [Stacker thesis, eq. 3.12-3.17]. With nothing in range d_min is the sensor range; v_obs is capped at v_des so
  // that obstacles can only slow the stacker down (the thesis leaves v_obs open when no obstacle is seen).
  out.potential = field.potential;
  out.alpha = speed_threshold(field.potential, params_.c);
  out.min_clearance = field.min_clearance;
  out.v_obs = std::min(std::min(field.min_clearance, params_.sensor_range) / params_.time_to_contact, v_des);
  const double c_obs = params_.c_v_obs * (0.5 + out.alpha);
  const double c_tar = params_.c_v_tar * (0.5 - out.alpha);
  const double c_sum = c_obs + c_tar;
  if (dt > 0.0 && c_sum > 0.0) {
    const double settled = (c_obs * out.v_obs + c_tar * v_des) / c_sum;
    speed_ = settled + (speed_ - settled) * std::exp(-c_sum * dt);
  }
  out.speed = speed_;
  // [Stacker thesis, Algorithm 3] with the inverse kinematics [Stacker thesis, eq. 5.17] on the signed speed dir * v.
  out.command = sim::inverse_kinematics({dir * speed_, out.heading_rate}, geometry_.wheelbase);
  return out;
}

}  // namespace fleet::control
