#pragma once

#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

namespace fleet::perception {

// The depth-camera model shared by the simulated cameras (core/sim) and the pallet detector: the
// image, the pinhole geometry and the mounting pose. Header-only so that the simulator can use it
// without linking the perception library.

/// A point or direction in the robot body frame: x forward, y left, z up from the floor (REP-103).
struct Vec3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;

  friend Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend Vec3 operator*(double k, Vec3 a) { return {k * a.x, k * a.y, k * a.z}; }
};

inline double dot(Vec3 a, Vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline double norm(Vec3 a) {
  return std::sqrt(dot(a, a));
}

/// Where a camera sits on the robot, in the body frame. The optical axis is first tilted, then
/// panned: a pan-tilt unit turns about the vertical axis, then about the camera's own
/// horizontal axis, so the image never rolls.
struct CameraMount {
  double x = 0.0;     ///< metres ahead of the body origin
  double y = 0.0;     ///< metres to the left
  double z = 0.0;     ///< optical centre height above the floor, metres
  double pan = 0.0;   ///< rad, counter-clockwise from the body's +x (pi looks backwards)
  double tilt = 0.0;  ///< rad, positive looks up: the thesis's "tilt -50 deg" looks down
};

/// A pinhole depth camera. Fields of view are full angles across the image; pixels need not be
/// square (the focal lengths follow from each field of view separately).
struct DepthCameraModel {
  int width = 0;           ///< pixels
  int height = 0;          ///< pixels
  double hfov = 0.0;       ///< horizontal field of view, rad
  double vfov = 0.0;       ///< vertical field of view, rad
  double min_range = 0.0;  ///< closer returns are dropped, metres along the ray
  double max_range = 0.0;  ///< farther returns are dropped, metres along the ray
  CameraMount mount;

  double fx() const { return 0.5 * width / std::tan(0.5 * hfov); }
  double fy() const { return 0.5 * height / std::tan(0.5 * vfov); }
  /// Angle one pixel spans horizontally at the image centre, rad.
  double pixel_angle() const { return hfov / width; }
};

/// A rectangle of pixels, columns [col0, col1) and rows [row0, row1).
struct PixelWindow {
  int col0 = 0;
  int col1 = 0;
  int row0 = 0;
  int row1 = 0;
  bool empty() const { return col0 >= col1 || row0 >= row1; }
  bool contains(int col, int row) const { return col >= col0 && col < col1 && row >= row0 && row < row1; }
};

/// A depth image, row-major, row 0 at the top, column 0 at the left. Each value is the depth
/// along the optical axis in metres (the convention of REP-118 and of the RealSense SDK, not the
/// range along the ray); NaN where there is no return.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<float> depth;

  static constexpr float kNoReturn = std::numeric_limits<float>::quiet_NaN();

  float at(int col, int row) const { return depth[static_cast<std::size_t>(row) * width + col]; }
  bool has_return(int col, int row) const { return !std::isnan(at(col, row)); }
};

/// The camera's optical centre in the body frame.
inline Vec3 camera_origin(const DepthCameraModel& camera) {
  return {camera.mount.x, camera.mount.y, camera.mount.z};
}

/// The camera axes in the body frame: forward (optical axis), left, up.
struct CameraAxes {
  Vec3 forward;
  Vec3 left;
  Vec3 up;
};

inline CameraAxes camera_axes(const CameraMount& mount) {
  const double cp = std::cos(mount.pan);
  const double sp = std::sin(mount.pan);
  const double ct = std::cos(mount.tilt);
  const double st = std::sin(mount.tilt);
  return {{cp * ct, sp * ct, st}, {-sp, cp, 0.0}, {-cp * st, -sp * st, ct}};
}

/// The ray through image position (col, row) (pixel centres at +0.5) in the body frame, scaled
/// so that its component along the optical axis is 1: origin + depth * ray is the 3-D point.
/// The focal lengths (a tangent each) are computed once per camera, for many pixels.
class PixelRays {
 public:
  PixelRays(const DepthCameraModel& camera, const CameraAxes& axes)
      : axes_(axes),
        half_width_(0.5 * camera.width),
        half_height_(0.5 * camera.height),
        fx_(camera.fx()),
        fy_(camera.fy()) {}
  Vec3 operator()(double col, double row) const {
    return axes_.forward + ((half_width_ - col) / fx_) * axes_.left + ((half_height_ - row) / fy_) * axes_.up;
  }

 private:
  CameraAxes axes_;
  double half_width_;
  double half_height_;
  double fx_;
  double fy_;
};

/// The same ray for one pixel.
inline Vec3 pixel_ray(const DepthCameraModel& camera, const CameraAxes& axes, double col, double row) {
  return PixelRays(camera, axes)(col, row);
}

/// The 3-D point a pixel sees, in the body frame; nullopt where the pixel has no return.
inline std::optional<Vec3> pixel_point(const DepthCameraModel& camera, const DepthImage& image, int col, int row) {
  const float d = image.at(col, row);
  if (std::isnan(d)) return std::nullopt;
  const Vec3 ray = pixel_ray(camera, camera_axes(camera.mount), col + 0.5, row + 0.5);
  return camera_origin(camera) + static_cast<double>(d) * ray;
}

/// Where a body-frame point falls in the image (col, row in pixels); nullopt behind the camera.
struct ImagePoint {
  double col = 0.0;
  double row = 0.0;
};

inline std::optional<ImagePoint> project(const DepthCameraModel& camera, const CameraAxes& axes, Vec3 point) {
  const Vec3 rel = point - camera_origin(camera);
  const double forward = dot(rel, axes.forward);
  if (forward <= 1e-6) return std::nullopt;
  return ImagePoint{0.5 * camera.width - camera.fx() * dot(rel, axes.left) / forward,
                    0.5 * camera.height - camera.fy() * dot(rel, axes.up) / forward};
}

}  // namespace fleet::perception
