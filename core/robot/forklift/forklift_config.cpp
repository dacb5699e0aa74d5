#include <algorithm>
#include <stdexcept>

#include "robot/forklift/forklift.hpp"
#include "vehicle/vehicle_types.hpp"

namespace fleet::robot {

ForkliftConfig ForkliftConfig::defaults() {
  ForkliftConfig c;
  c.task.follower = control::FollowerParams::regulated();
  return c;
}

namespace {

/// The forklift type's own profile: the thesis's table robot every default is tuned for.
const vehicle::VehicleProfile& table_profile() {
  static const vehicle::VehicleProfile profile = vehicle::find_robot_type("forklift")->defaults;
  return profile;
}

/// `value / reference`, or 1 where the profile leaves the quantity unset.
double ratio(double value, double reference) {
  return value > 0.0 ? value / reference : 1.0;
}

void scale_follower(control::FollowerParams& f, double length, double speed, double accel, double slow_distance) {
  f.v_max *= speed;
  f.lookahead *= length;
  f.goal_tolerance *= length;
  f.back_in_up_to *= length;
  f.reverse_legs_up_to *= length;
  f.regulate_min_radius *= length;
  f.obstacle_stop_distance *= length;
  f.obstacle_slow_distance = slow_distance;
  f.regulated_min_speed *= std::min(length, speed);
  f.max_linear_accel *= accel;
  // The same turn-rate change sweeps the body's ends `length` times faster.
  f.max_angular_accel *= accel / length;
}

}  // namespace

ForkliftConfig ForkliftConfig::for_vehicle(const vehicle::VehicleProfile& profile) {
  const vehicle::VehicleProfile& table = table_profile();
  const geometry::Footprint size = profile.extent();
  const geometry::Footprint table_size = table.extent();
  if (!(size.length > 0.0 && size.width > 0.0)) throw std::invalid_argument("for_vehicle: empty footprint");
  // Every factor is exactly 1 for the table profile (x / x), so the defaults come back bit for bit.
  const double s = size.length / table_size.length;  // lengths: forks, camera, tolerances, gaps
  const double w = size.width / table_size.width;    // the wheel track
  const double kv = ratio(profile.max_speed, table.max_speed);
  const double ka = ratio(profile.max_acceleration, table.max_acceleration);
  // Manoeuvres (servoing, placing, escaping) keep their shape: speeds grow with the distances
  // they cover, but never faster than the vehicle's speed grows. Their times grow by s / sv.
  const double sv = std::min(s, kv);

  ForkliftConfig c = defaults();
  auto& body = c.sim.forklift;
  body.footprint = size;
  body.mecanum.wheel_radius *= s;
  body.mecanum.half_wheelbase *= s;
  body.mecanum.half_track *= w;
  // Top wheel speed: pure translation with every wheel at its limit is the profile's top speed
  // (0.3 m/s on the table).
  body.mecanum.max_wheel_speed *= kv / s;
  c.sim.uwb.antenna_offset = s * c.sim.uwb.antenna_offset;
  c.sim.ekf.antenna_offset = s * c.sim.ekf.antenna_offset;
  c.sim.ekf.heading_init_distance *= s;
  for (int i : {0, 1}) {
    c.sim.ekf.commanded_velocity_std[i] *= kv;
    c.sim.ekf.encoder_velocity_std[i] *= kv;
  }

  // The obstacle slow-down starts where braking at 80 % of the acceleration limit from top speed
  // still stops at the stop distance, and never closer than the table's 0.30 m scaled.
  const control::FollowerParams table_follower = control::FollowerParams::regulated();
  const double v_top = table.max_speed * kv;
  const double a_brake = 0.8 * table_follower.max_linear_accel * ka;
  const double slow_distance = std::max(table_follower.obstacle_slow_distance * s,
                                        table_follower.obstacle_stop_distance * s + v_top * v_top / (2.0 * a_brake));
  const double slow_factor = slow_distance / table_follower.obstacle_slow_distance;
  scale_follower(c.task.follower, s, kv, ka, slow_distance);
  auto& approach = c.task.search.approach;
  approach.v_max *= sv;
  approach.lookahead *= s;
  approach.goal_tolerance *= s;

  auto& g = c.task.geometry;
  g.camera_x *= s;
  g.carry_x *= s;
  g.marker_offset *= s;
  c.task.search.standoff *= s;
  c.task.search.match_radius *= s;
  auto& pick = c.task.pick;
  pick.v_minx *= sv;
  pick.v_miny *= sv;
  pick.drive_in_speed *= sv;
  pick.d_min *= s;
  pick.d_tol *= s;
  pick.timeout *= s / sv;
  auto& place = c.task.place;
  place.lateral_tol *= s;
  place.longitudinal_tol *= s;
  place.vx_limit *= sv;
  place.vy_limit *= sv;
  place.v_floor *= sv;
  place.back_out_distance *= s;
  place.back_out_speed *= sv;
  place.timeout *= s / sv;
  c.task.arrival_tolerance *= s;

  // A marker and a pallet as big as the vehicle look the same from as many body lengths away.
  c.camera.range_min *= s;
  c.camera.range_max *= s;
  c.camera.sigma_d *= s;
  c.pallet_world.lift_lateral_tol *= s;
  c.pallet_world.lift_depth_tol *= s;

  c.grid_resolution *= s;
  c.lidar.max_range *= s;
  c.lidar.min_range *= s;
  c.safety_gap *= s;
  c.stop_distance *= s;
  c.neighbour_margin *= s;
  c.neighbour_max_speed *= kv;
  c.neighbour_max_reach *= kv;
  c.reported_tolerance *= s;
  c.robot_height *= s;
  if (c.anchor_shadow_margin >= 0.0) c.anchor_shadow_margin *= s;
  // The path is checked at least as far ahead as the follower starts slowing down.
  c.clearance_lookahead *= slow_factor;
  c.clearance_sample *= s;
  c.clearance_margin *= s;
  c.temporary_size *= s;
  // The body's reach plus what the stop's horizon covers at top speed.
  c.safety_scan_range *= std::max(s, kv);
  c.escape_within *= s;
  c.escape_speed *= sv;
  c.stop_moved *= s;
  c.uwb_shadow_reach *= s;
  c.siding_end_margin *= s;
  return c;
}

}  // namespace fleet::robot
