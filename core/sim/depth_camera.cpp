#include "sim/depth_camera.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "geometry/pose.hpp"

namespace fleet::sim {

using perception::Vec3;

namespace {

using ::fleet::geometry::kDeg;

Box3 make_box(double x0, double x1, double y0, double y1, double z0, double z1) {
  return {{x0, y0, z0}, {x1, y1, z1}};
}

Box3 enclosing(const std::vector<Box3>& boxes) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Box3 b{{inf, inf, inf}, {-inf, -inf, -inf}};
  for (const Box3& box : boxes) {
    b.min = {std::min(b.min.x, box.min.x), std::min(b.min.y, box.min.y), std::min(b.min.z, box.min.z)};
    b.max = {std::max(b.max.x, box.max.x), std::max(b.max.y, box.max.y), std::max(b.max.z, box.max.z)};
  }
  return b;
}

// SplitMix64's finaliser: a well-mixed 64-bit value from a counter (Steele, Lea and Flood, 2014).
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// A unit normal drawn from `key` alone (Box-Muller on the two halves of its hash), so that a
// pixel's noise depends on its frame and index and not on which other pixels were drawn.
double unit_normal(std::uint64_t key) {
  const std::uint64_t bits = mix(key);
  const double u1 = (static_cast<double>(bits >> 32) + 0.5) / 4294967296.0;  // (0, 1): the log stays finite
  const double u2 = static_cast<double>(bits & 0xffffffffULL) / 4294967296.0;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

// Reciprocal of a direction component; an exact zero becomes a huge value of the right sign
// so that the slab test still classifies the ray correctly.
double safe_inverse(double v) {
  constexpr double big = 1e30;
  if (v == 0.0) return big;
  return 1.0 / v;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Scene

std::vector<Box3> epal_pallet_boxes(const EpalDimensions& d) {
  std::vector<Box3> boxes;
  const double hx = 0.5 * d.length;
  const double hy = 0.5 * d.width;
  const double z_block = d.board;                   // top of the bottom boards
  const double z_cross = z_block + d.block_height;  // top of the blocks
  const double z_deck = z_cross + d.board;          // top of the cross boards
  const double z_top = z_deck + d.board;            // top of the deck
  // The three rows of blocks and cross boards, at both ends and in the middle of the length.
  const double row_x[3][2] = {
      {-hx, -hx + d.block_depth}, {-0.5 * d.block_depth, 0.5 * d.block_depth}, {hx - d.block_depth, hx}};
  // The three columns across the width: outer, middle, outer.
  const double col_y[3][2] = {
      {-hy, -hy + d.outer_block}, {-0.5 * d.middle_block, 0.5 * d.middle_block}, {hy - d.outer_block, hy}};
  for (const auto& y : col_y) boxes.push_back(make_box(-hx, hx, y[0], y[1], 0.0, z_block));  // bottom boards
  for (const auto& x : row_x) {
    for (const auto& y : col_y) boxes.push_back(make_box(x[0], x[1], y[0], y[1], z_block, z_cross));  // blocks
    boxes.push_back(make_box(x[0], x[1], -hy, hy, z_cross, z_deck));                                  // cross boards
  }
  // Five deck boards with four equal gaps between them (41.25 mm on an EPAL).
  const double gap = (d.width - 2.0 * d.outer_deck - 2.0 * d.inner_deck - d.centre_deck) / 4.0;
  const double widths[5] = {d.outer_deck, d.inner_deck, d.centre_deck, d.inner_deck, d.outer_deck};
  double y = -hy;
  for (double w : widths) {
    boxes.push_back(make_box(-hx, hx, y, y + w, z_deck, z_top));
    y += w + gap;
  }
  return boxes;
}

std::size_t DepthScene::add(const geometry::Pose2& pose, std::vector<Box3> boxes, double base_height) {
  for (Box3& b : boxes) {
    b.min.z += base_height;
    b.max.z += base_height;
  }
  SceneObject object{pose, std::move(boxes), {}};
  object.bounds = enclosing(object.boxes);
  objects_.push_back(std::move(object));
  return objects_.size() - 1;
}

std::size_t DepthScene::add_pallet(const geometry::Pose2& pose, double base_height, const EpalDimensions& dims) {
  return add(pose, epal_pallet_boxes(dims), base_height);
}

std::size_t DepthScene::add_limiter(const geometry::Pose2& pose, double length, double depth, double height) {
  return add(pose, {make_box(-0.5 * length, 0.5 * length, -0.5 * depth, 0.5 * depth, 0.0, height)});
}

// ---------------------------------------------------------------------------------------------
// Ray casting

double ray_box(const Vec3& origin, const Vec3& inv_direction, const Box3& box, double t_min, double t_max) {
  // Slab method: intersect the ray's parameter interval with each axis's slab.
  const double o[3] = {origin.x, origin.y, origin.z};
  const double inv[3] = {inv_direction.x, inv_direction.y, inv_direction.z};
  const double lo[3] = {box.min.x, box.min.y, box.min.z};
  const double hi[3] = {box.max.x, box.max.y, box.max.z};
  for (int axis = 0; axis < 3; ++axis) {
    double t0 = (lo[axis] - o[axis]) * inv[axis];
    double t1 = (hi[axis] - o[axis]) * inv[axis];
    if (t0 > t1) std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
    if (t_min > t_max) return -1.0;
  }
  return t_min;
}

namespace {

// An object with the ray origin already in its frame, so that each ray only rotates its direction,
// and the image rectangle its bounds project to, so that most pixels skip it.
struct PreparedObject {
  const SceneObject* object;
  double cos_yaw;
  double sin_yaw;
  Vec3 local_origin;
  int col0 = 0, col1 = std::numeric_limits<int>::max(), row0 = 0, row1 = std::numeric_limits<int>::max();
  bool covers(int col, int row) const { return col >= col0 && col < col1 && row >= row0 && row < row1; }
};

std::vector<PreparedObject> prepare(const DepthScene& scene, const Vec3& origin) {
  std::vector<PreparedObject> prepared;
  prepared.reserve(scene.objects().size());
  for (const SceneObject& object : scene.objects()) {
    const double c = std::cos(object.pose.yaw);
    const double s = std::sin(object.pose.yaw);
    const double dx = origin.x - object.pose.x;
    const double dy = origin.y - object.pose.y;
    prepared.push_back({&object, c, s, {c * dx + s * dy, -s * dx + c * dy, origin.z}});
  }
  return prepared;
}

// Narrows each object to the pixels its bounding box can cover; an object reaching behind the
// camera keeps the whole image.
void restrict_to_image(std::vector<PreparedObject>& objects, const perception::DepthCameraModel& m, const Vec3& origin,
                       const Vec3& forward, const Vec3& left, const Vec3& up) {
  for (PreparedObject& p : objects) {
    const Box3& b = p.object->bounds;
    double col_min = 1e300, col_max = -1e300, row_min = 1e300, row_max = -1e300;
    bool behind = false;
    for (int corner = 0; corner < 8 && !behind; ++corner) {
      const double lx = corner & 1 ? b.max.x : b.min.x;
      const double ly = corner & 2 ? b.max.y : b.min.y;
      const Vec3 world{p.object->pose.x + p.cos_yaw * lx - p.sin_yaw * ly,
                       p.object->pose.y + p.sin_yaw * lx + p.cos_yaw * ly, corner & 4 ? b.max.z : b.min.z};
      const Vec3 rel = world - origin;
      const double ahead = perception::dot(rel, forward);
      if (ahead <= 1e-6) {
        behind = true;
        break;
      }
      const double col = 0.5 * m.width - m.fx() * perception::dot(rel, left) / ahead;
      const double row = 0.5 * m.height - m.fy() * perception::dot(rel, up) / ahead;
      col_min = std::min(col_min, col);
      col_max = std::max(col_max, col);
      row_min = std::min(row_min, row);
      row_max = std::max(row_max, row);
    }
    if (behind) continue;
    // One pixel of slack: a ray through a pixel centre is tested wherever the box may touch it.
    p.col0 = static_cast<int>(std::floor(std::max(col_min, -1.0))) - 1;
    p.col1 = static_cast<int>(std::ceil(std::min(col_max, m.width + 1.0))) + 1;
    p.row0 = static_cast<int>(std::floor(std::max(row_min, -1.0))) - 1;
    p.row1 = static_cast<int>(std::ceil(std::min(row_max, m.height + 1.0))) + 1;
  }
}

double cast_prepared(bool floor, const std::vector<PreparedObject>& objects, const Vec3& origin, const Vec3& direction,
                     double t_max, int col = 0, int row = 0) {
  double nearest = -1.0;
  if (floor && direction.z < 0.0 && origin.z > 0.0) {
    const double t = -origin.z / direction.z;
    if (t <= t_max) {
      nearest = t;
      t_max = t;
    }
  }
  for (const PreparedObject& p : objects) {
    if (!p.covers(col, row)) continue;
    const Vec3 local_direction{p.cos_yaw * direction.x + p.sin_yaw * direction.y,
                               -p.sin_yaw * direction.x + p.cos_yaw * direction.y, direction.z};
    const Vec3 inv{safe_inverse(local_direction.x), safe_inverse(local_direction.y), safe_inverse(local_direction.z)};
    if (ray_box(p.local_origin, inv, p.object->bounds, 0.0, t_max) < 0.0) continue;
    for (const Box3& box : p.object->boxes) {
      const double t = ray_box(p.local_origin, inv, box, 0.0, t_max);
      if (t >= 0.0) {
        nearest = t;
        t_max = t;
      }
    }
  }
  return nearest;
}

}  // namespace

double cast_ray(const DepthScene& scene, const Vec3& origin, const Vec3& direction, double t_max) {
  return cast_prepared(scene.floor, prepare(scene, origin), origin, direction, t_max);
}

// ---------------------------------------------------------------------------------------------
// Camera

DepthCameraParams sick_3vistor_t(double pan) {
  DepthCameraParams p;
  p.model.width = 176;
  p.model.height = 144;
  p.model.hfov = 69.0 * kDeg;
  p.model.vfov = 56.0 * kDeg;
  p.model.min_range = 0.5;
  p.model.max_range = 7.2;
  p.model.mount = {0.70, 0.0, 1.64, pan, -50.0 * kDeg};
  p.noise = {0.004, 0.004, 0.0};
  return p;
}

DepthCameraParams realsense_r200() {
  DepthCameraParams p;
  p.model.width = 640;
  p.model.height = 480;
  p.model.hfov = 59.0 * kDeg;
  p.model.vfov = 46.0 * kDeg;
  p.model.min_range = 0.5;
  p.model.max_range = 3.5;
  p.model.mount = {-0.85, 0.0, 0.50, std::numbers::pi, -10.0 * kDeg};
  p.noise = {0.001, 0.0, 0.003};
  return p;
}

DepthCamera::DepthCamera(DepthCameraParams params, std::uint64_t seed) : params_(params), seed_(seed) {}

void DepthCamera::set_pan_tilt(double pan, double tilt) {
  params_.model.mount.pan = pan;
  params_.model.mount.tilt = tilt;
}

perception::DepthImage DepthCamera::render(const DepthScene& scene, const geometry::Pose2& robot_pose,
                                           const std::optional<perception::PixelWindow>& window) {
  const perception::DepthCameraModel& m = params_.model;
  const perception::PixelWindow whole{0, m.width, 0, m.height};
  const std::uint64_t frame_key = mix(seed_ ^ mix(++frames_));
  if (!window) return render_impl(scene, robot_pose, whole, frame_key);
  const perception::PixelWindow clipped{std::max(window->col0, 0), std::min(window->col1, m.width),
                                        std::max(window->row0, 0), std::min(window->row1, m.height)};
  return render_impl(scene, robot_pose, clipped, frame_key);
}

perception::DepthImage DepthCamera::render_ideal(const DepthScene& scene, const geometry::Pose2& robot_pose) const {
  return render_impl(scene, robot_pose, {0, params_.model.width, 0, params_.model.height}, std::nullopt);
}

perception::DepthImage DepthCamera::render_impl(const DepthScene& scene, const geometry::Pose2& robot_pose,
                                                const perception::PixelWindow& window,
                                                std::optional<std::uint64_t> frame_key) const {
  const perception::DepthCameraModel& m = params_.model;
  perception::DepthImage image{
      m.width, m.height,
      std::vector<float>(static_cast<std::size_t>(m.width) * m.height, perception::DepthImage::kNoReturn)};
  // Camera axes and origin in the map frame: the robot turns the body-frame axes by its yaw.
  const perception::CameraAxes body_axes = perception::camera_axes(m.mount);
  const double c = std::cos(robot_pose.yaw);
  const double s = std::sin(robot_pose.yaw);
  const auto to_map = [&](const Vec3& v) { return Vec3{c * v.x - s * v.y, s * v.x + c * v.y, v.z}; };
  const Vec3 forward = to_map(body_axes.forward);
  const Vec3 left = to_map(body_axes.left);
  const Vec3 up = to_map(body_axes.up);
  const Vec3 origin = to_map(perception::camera_origin(m)) + Vec3{robot_pose.x, robot_pose.y, 0.0};
  const double fx = m.fx();
  const double fy = m.fy();
  std::vector<PreparedObject> objects = prepare(scene, origin);
  restrict_to_image(objects, m, origin, forward, left, up);
  for (int row = window.row0; row < window.row1; ++row) {
    const double b = (0.5 * m.height - (row + 0.5)) / fy;
    const Vec3 row_base = forward + b * up;
    for (int col = window.col0; col < window.col1; ++col) {
      const double a = (0.5 * m.width - (col + 0.5)) / fx;
      // A ray with unit optical-axis component: its parameter is the depth, its length per
      // unit depth converts depth to range.
      const Vec3 ray = row_base + a * left;
      const double range_per_depth = perception::norm(ray);
      float& out = image.depth[static_cast<std::size_t>(row) * m.width + col];
      const double depth = cast_prepared(scene.floor, objects, origin, ray, m.max_range / range_per_depth, col, row);
      double range = depth * range_per_depth;
      if (depth < 0.0 || range < m.min_range) {
        out = perception::DepthImage::kNoReturn;
        continue;
      }
      if (frame_key) {
        range += params_.noise.sigma(range) * unit_normal(*frame_key + static_cast<std::uint64_t>(row) * m.width + col);
      }
      out = range < m.min_range || range > m.max_range ? perception::DepthImage::kNoReturn
                                                       : static_cast<float>(range / range_per_depth);
    }
  }
  return image;
}

}  // namespace fleet::sim
