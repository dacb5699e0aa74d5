#include "perception/detection_sweep.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>

namespace fleet::perception {

namespace {

SweepPoint run_case(const SweepSetup& setup, double distance, double angle) {
  const double length = setup.detector.pallet.length;
  const geometry::Pose2 truth = pallet_ahead_of_camera(setup.camera, distance, angle, length);
  PalletExpectation expected;
  expected.pallet = pallet_ahead_of_camera(setup.camera, distance, 0.0, length);
  expected.base_height = setup.base_height;
  expected.area = setup.area;
  const Detection d = detect_pallet(setup.render(truth), setup.camera, expected, setup.detector);

  SweepPoint point{distance, angle, d.found, false, 0.0, 0.0, d.reason};
  if (!d.found) return point;
  // The truth seen the detector's way: the face midpoint and the yaw out of the seen face.
  const double face_yaw = truth.yaw;  // pallet_ahead_of_camera turns the entry face's yaw
  const geometry::Vec2 face_mid =
      truth.position() + 0.5 * length * geometry::Vec2{std::cos(face_yaw), std::sin(face_yaw)};
  point.midpoint_error = geometry::distance(d.midpoint, face_mid);
  point.yaw_error = geometry::angle_diff(d.yaw, face_yaw);
  point.success = point.midpoint_error <= setup.midpoint_tolerance && std::abs(point.yaw_error) <= setup.yaw_tolerance;
  if (!point.success) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "detected %.3f m and %.2f deg from the truth", point.midpoint_error,
                  point.yaw_error * 180.0 / std::numbers::pi);
    point.reason = buf;
  }
  return point;
}

std::vector<double> values(SweepAxis axis) {
  std::vector<double> v;
  if (axis.step <= 0.0) return {axis.first};
  const int n = static_cast<int>(std::floor((axis.last - axis.first) / axis.step + 1e-6));
  for (int i = 0; i <= n; ++i) v.push_back(axis.first + i * axis.step);
  return v;
}

void longest_success_run(SweepResult& result, bool by_distance) {
  std::size_t best_begin = 0, best_len = 0;
  for (std::size_t i = 0; i < result.points.size();) {
    if (!result.points[i].success) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < result.points.size() && result.points[j].success) ++j;
    if (j - i > best_len) {
      best_begin = i;
      best_len = j - i;
    }
    i = j;
  }
  result.any = best_len > 0;
  if (!result.any) return;
  const SweepPoint& first = result.points[best_begin];
  const SweepPoint& last = result.points[best_begin + best_len - 1];
  result.lo = by_distance ? first.distance : first.angle;
  result.hi = by_distance ? last.distance : last.angle;
}

}  // namespace

geometry::Pose2 pallet_ahead_of_camera(const DepthCameraModel& camera, double distance, double angle,
                                       double pallet_length) {
  const double pan = camera.mount.pan;
  const double centre_distance = distance + 0.5 * pallet_length;
  // The entry face looks back at the camera: its outward yaw is the pan reversed, then turned.
  return {camera.mount.x + centre_distance * std::cos(pan), camera.mount.y + centre_distance * std::sin(pan),
          geometry::normalize_angle(pan + std::numbers::pi + angle)};
}

SweepResult sweep_distance(const SweepSetup& setup, SweepAxis distances) {
  SweepResult result;
  for (double d : values(distances)) result.points.push_back(run_case(setup, d, 0.0));
  longest_success_run(result, true);
  return result;
}

SweepResult sweep_angle(const SweepSetup& setup, double distance, SweepAxis angles) {
  SweepResult result;
  for (double a : values(angles)) result.points.push_back(run_case(setup, distance, a));
  longest_success_run(result, false);
  return result;
}

}  // namespace fleet::perception
