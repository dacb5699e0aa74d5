#pragma once

#include <cmath>
#include <numbers>

namespace fleet::geometry {

/// One degree in radians: an angle given in degrees is written `20.0 * kDeg`.
inline constexpr double kDeg = std::numbers::pi / 180.0;

struct Vec2 {
  double x = 0.0;
  double y = 0.0;

  friend Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
  friend Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
  friend Vec2 operator*(double k, Vec2 a) { return {k * a.x, k * a.y}; }
  friend Vec2 operator*(Vec2 a, double k) { return {k * a.x, k * a.y}; }
  friend bool operator==(Vec2 a, Vec2 b) = default;
};

inline double dot(Vec2 a, Vec2 b) {
  return a.x * b.x + a.y * b.y;
}
inline double cross(Vec2 a, Vec2 b) {
  return a.x * b.y - a.y * b.x;
}
inline double norm(Vec2 a) {
  return std::hypot(a.x, a.y);
}
inline double distance(Vec2 a, Vec2 b) {
  return norm(a - b);
}

/// Wraps an angle to [-pi, pi).
inline double normalize_angle(double a) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  a = std::fmod(a + std::numbers::pi, two_pi);
  if (a < 0.0) a += two_pi;
  return a - std::numbers::pi;
}

/// Signed smallest difference a - b, in [-pi, pi).
inline double angle_diff(double a, double b) {
  return normalize_angle(a - b);
}

/// A planar pose in the map frame: x right, y up, yaw counter-clockwise from +x (REP-103).
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;

  Vec2 position() const { return {x, y}; }
  friend bool operator==(const Pose2&, const Pose2&) = default;
};

/// Maps a point given in the body frame of `pose` (x forward, y left) into the map frame.
inline Vec2 body_to_map(const Pose2& pose, Vec2 body) {
  const double c = std::cos(pose.yaw);
  const double s = std::sin(pose.yaw);
  return {pose.x + c * body.x - s * body.y, pose.y + s * body.x + c * body.y};
}

/// Maps a map-frame point into the body frame of `pose`.
inline Vec2 map_to_body(const Pose2& pose, Vec2 map) {
  const double c = std::cos(pose.yaw);
  const double s = std::sin(pose.yaw);
  const Vec2 d = map - pose.position();
  return {c * d.x + s * d.y, -s * d.x + c * d.y};
}

/// A pose given in the body frame of `pose` (a pallet the robot sees, say) in the map frame.
inline Pose2 body_pose_to_map(const Pose2& pose, const Pose2& body) {
  const Vec2 p = body_to_map(pose, body.position());
  return {p.x, p.y, normalize_angle(pose.yaw + body.yaw)};
}

/// A map-frame pose in the body frame of `pose`.
inline Pose2 map_pose_to_body(const Pose2& pose, const Pose2& map) {
  const Vec2 p = map_to_body(pose, map.position());
  return {p.x, p.y, angle_diff(map.yaw, pose.yaw)};
}

inline bool is_finite(const Pose2& p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.yaw);
}

}  // namespace fleet::geometry
