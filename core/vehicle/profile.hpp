#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::vehicle {

/// How the wheels move the body, in VDA 5050 factsheet terms (typeSpecification.agvKinematic).
enum class Kinematics { kOmni, kDifferential, kTricycle };

std::string_view to_string(Kinematics kinematics);
std::optional<Kinematics> parse_kinematics(std::string_view text);

/// What a vehicle carries and how high it lifts it.
struct LoadHandling {
  std::string load_type = "pallet";  ///< "pallet", "box" or "none"
  double max_mass = 0.0;             ///< kg
  double lift_height = 0.0;          ///< metres above the floor the load can be picked from or put at
};

/// Data about one kind of vehicle: its VDA 5050 factsheet. Two fleets may run the same robot type
/// with different profiles (a forklift and a reach truck both run `forklift`).
struct VehicleProfile {
  geometry::Polygon footprint;  ///< body frame, metres, counter-clockwise, a simple polygon
  Kinematics kinematics = Kinematics::kOmni;
  double wheelbase = 0.0;           ///< metres, tricycle only
  double max_steering_angle = 0.0;  ///< rad, tricycle only
  /// Body-frame x of the rear-axle midpoint, metres, tricycle only: the point that follows the
  /// route, so the body ahead of it swings out of a curve by more than its centre would.
  double rear_axle_x = 0.0;
  double max_speed = 0.0;         ///< m/s
  double max_acceleration = 0.0;  ///< m/s^2
  double max_yaw_rate = 0.0;      ///< rad/s
  LoadHandling load;
  /// The actions the vehicle performs at a place, by their VDA 5050 names (pick, drop, ...).
  std::vector<std::string> actions;

  bool can(std::string_view action) const;
  /// The footprint's axis-aligned extent in the body frame (what the rectangle-based code uses).
  geometry::Footprint extent() const;
};

/// A rectangle of `length` x `width` centred on the body origin, counter-clockwise.
geometry::Polygon rectangle(double length, double width);

/// Whether `polygon` has at least three distinct corners, non-zero area, and no two edges that
/// cross or touch except neighbours at their shared corner.
bool is_simple_polygon(const geometry::Polygon& polygon);

/// What is wrong with a profile: the key (`footprint`, `kinematics.wheelbase`, ...) and why.
struct ProfileError {
  std::string key;
  std::string message;
};

/// Empty when the profile is consistent.
std::optional<ProfileError> profile_error(const VehicleProfile& profile);

}  // namespace fleet::vehicle
