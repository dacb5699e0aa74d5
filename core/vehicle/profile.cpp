#include "vehicle/profile.hpp"

#include <algorithm>
#include <cmath>

namespace fleet::vehicle {

std::string_view to_string(Kinematics kinematics) {
  switch (kinematics) {
    case Kinematics::kOmni:
      return "omni";
    case Kinematics::kDifferential:
      return "differential";
    case Kinematics::kTricycle:
      return "tricycle";
  }
  return "omni";
}

std::optional<Kinematics> parse_kinematics(std::string_view text) {
  for (Kinematics k : {Kinematics::kOmni, Kinematics::kDifferential, Kinematics::kTricycle}) {
    if (to_string(k) == text) return k;
  }
  return std::nullopt;
}

bool VehicleProfile::can(std::string_view action) const {
  return std::find(actions.begin(), actions.end(), action) != actions.end();
}

geometry::Footprint VehicleProfile::extent() const {
  const geometry::Bounds b = geometry::bounding_box(footprint);
  // The rectangle code centres the footprint on the body origin: take the larger half on each axis
  // so the rectangle covers the polygon.
  const double half_length = std::max(std::abs(b.min_x), std::abs(b.max_x));
  const double half_width = std::max(std::abs(b.min_y), std::abs(b.max_y));
  return {2.0 * half_length, 2.0 * half_width};
}

geometry::Polygon rectangle(double length, double width) {
  const double hl = length / 2.0, hw = width / 2.0;
  return {{hl, -hw}, {hl, hw}, {-hl, hw}, {-hl, -hw}};
}

bool is_simple_polygon(const geometry::Polygon& polygon) {
  const std::size_t n = polygon.size();
  if (n < 3) return false;
  for (const auto& p : polygon) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
  }
  if (std::abs(geometry::signed_area(polygon)) < 1e-9) return false;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % n];
    if (std::hypot(b.x - a.x, b.y - a.y) < 1e-9) return false;
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool neighbours = j == i + 1 || (i == 0 && j == n - 1);
      if (neighbours) continue;
      if (geometry::segments_intersect(a, b, polygon[j], polygon[(j + 1) % n])) return false;
    }
  }
  return true;
}

std::optional<ProfileError> profile_error(const VehicleProfile& profile) {
  if (!is_simple_polygon(profile.footprint)) {
    return ProfileError{"footprint",
                        "not a simple polygon (at least 3 distinct corners, no crossing edges, non-zero area)"};
  }
  const geometry::Bounds b = geometry::bounding_box(profile.footprint);
  if (!(b.min_x < 0.0 && b.max_x > 0.0 && b.min_y < 0.0 && b.max_y > 0.0)) {
    return ProfileError{"footprint", "the body origin (0, 0) must lie inside the footprint's extent"};
  }
  if (profile.kinematics == Kinematics::kTricycle) {
    if (!(profile.wheelbase > 0.0))
      return ProfileError{"kinematics.wheelbase", "a tricycle needs a positive wheelbase"};
    if (!(profile.max_steering_angle > 0.0 && profile.max_steering_angle <= M_PI / 2 + 1e-4)) {
      return ProfileError{"kinematics.max_steering_angle", "a tricycle steers within (0, pi/2] rad"};
    }
    if (!(profile.rear_axle_x > b.min_x && profile.rear_axle_x < b.max_x)) {
      return ProfileError{"kinematics.rear_axle_x", "the rear axle must lie within the footprint's length"};
    }
  }
  if (!(profile.max_speed > 0.0)) return ProfileError{"max_speed", "must be positive"};
  if (!(profile.max_acceleration > 0.0)) return ProfileError{"max_acceleration", "must be positive"};
  if (!(profile.max_yaw_rate > 0.0)) return ProfileError{"max_yaw_rate", "must be positive"};
  if (profile.load.max_mass < 0.0 || profile.load.lift_height < 0.0) {
    return ProfileError{"load", "max_mass and lift_height must not be negative"};
  }
  return std::nullopt;
}

}  // namespace fleet::vehicle
