#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "geometry/pose.hpp"
#include "perception/depth_image.hpp"

namespace fleet::sim {

// ---------------------------------------------------------------------------------------------
// Scene: the floor and a few solid objects, each a set of axis-aligned boxes in its own frame.

/// An axis-aligned box in an object's frame (x forward along the object's yaw, y left, z up).
struct Box3 {
  perception::Vec3 min;
  perception::Vec3 max;
};

/// A rigid object standing on the floor at `pose` (yaw about the vertical axis), made of boxes.
struct SceneObject {
  geometry::Pose2 pose;
  std::vector<Box3> boxes;
  Box3 bounds;  ///< encloses every box; tested first so that most rays skip the object
};

/// EPAL (EUR 1) pallet dimensions, metres (EN 13698-1).
struct EpalDimensions {
  double length = 1.200;        ///< along the pallet's x (the fork entry direction)
  double width = 0.800;         ///< along y: the 800 mm face is the one the stacker enters
  double board = 0.022;         ///< thickness of every board (top deck, cross boards, bottom)
  double block_height = 0.078;  ///< the nine blocks
  double block_depth = 0.145;   ///< blocks and cross boards, along x
  double outer_block = 0.100;   ///< corner and edge blocks across the 800 mm face, along y
  double middle_block = 0.145;  ///< centre-line blocks, along y
  double outer_deck = 0.145;    ///< the two outer top deck boards, along y
  double inner_deck = 0.100;    ///< the two intermediate top deck boards, along y
  double centre_deck = 0.145;   ///< the centre top deck board, along y
  double height() const { return 3.0 * board + block_height; }  ///< 0.144
};

/// The boxes of an EPAL pallet in its own frame: origin at the centre of its footprint on the
/// floor, x along the 1200 mm length, so both 800 mm faces (x = +-0.6) show the fork pockets.
/// Bottom to top: three bottom boards along x (100, 145, 100 mm wide), nine blocks 78 mm high,
/// three cross boards along y, five top deck boards along x. Seen from an 800 mm face: three
/// columns (100, 145, 100 mm: bottom board plus block) and two pockets 227.5 mm wide and 100 mm
/// high, under a 22 mm cross board and the ends of the deck boards. (The thesis calls the
/// columns "the same width" [Stacker thesis, section 5.4]; a real EPAL's outer ones are narrower.)
std::vector<Box3> epal_pallet_boxes(const EpalDimensions& dims = {});

/// The floor (z = 0) plus objects. Pallets and the safety limiter are objects like any other.
class DepthScene {
 public:
  bool floor = true;

  /// Adds an EPAL pallet whose footprint centre is at `pose`, standing on a surface
  /// `base_height` above the floor; returns its index in objects().
  std::size_t add_pallet(const geometry::Pose2& pose, double base_height = 0.0, const EpalDimensions& dims = {});
  /// Adds the raised safety limiter of the finished-goods row [Stacker thesis, sections 4.1.2-4.1.3]: a
  /// box `length` long (along the pose's x), `depth` deep and `height` high, centred on `pose`.
  /// The thesis says the limiter makes the pallets stand 0.30 m above the ground, so the row's
  /// pallets go on top of it (add_pallet with base_height = height).
  std::size_t add_limiter(const geometry::Pose2& pose, double length, double depth, double height = 0.30);
  /// Adds any object made of boxes, `base_height` above the floor.
  std::size_t add(const geometry::Pose2& pose, std::vector<Box3> boxes, double base_height = 0.0);

  const std::vector<SceneObject>& objects() const { return objects_; }

 private:
  std::vector<SceneObject> objects_;
};

/// Distance along a ray (origin + t * direction, t in [t_min, t_max]) to the first box hit by the
/// slab method, or a negative value when it misses.
double ray_box(const perception::Vec3& origin, const perception::Vec3& inv_direction, const Box3& box, double t_min,
               double t_max);

/// Distance along a world-frame ray to the nearest surface of the scene, or a negative value.
/// `direction` need not be unit: the result is in units of it.
double cast_ray(const DepthScene& scene, const perception::Vec3& origin, const perception::Vec3& direction,
                double t_max);

// ---------------------------------------------------------------------------------------------
// Camera

/// Gaussian range noise whose standard deviation grows with the range r along the ray:
/// sigma(r) = constant + linear * r + quadratic * r^2 (a time-of-flight sensor grows about
/// linearly, a stereo pair about quadratically). The thesis gives no noise model [Stacker thesis,
/// section 4.2.2], so the presets choose plausible values.
struct RangeNoise {
  double constant = 0.0;   ///< metres
  double linear = 0.0;     ///< metres per metre
  double quadratic = 0.0;  ///< metres per square metre
  double sigma(double range) const { return constant + (linear + quadratic * range) * range; }
};

struct DepthCameraParams {
  perception::DepthCameraModel model;
  RangeNoise noise;
};

/// The SICK 3Vistor-T time-of-flight camera on the stacker's pan-tilt unit [Stacker thesis,
/// Table 4.3, section 6.3, section 7.1.2]: 176 x 144 px, 69 x 56 deg, 0.5-7.2 m, optical centre
/// 1.64 m above the floor, tilted 50 deg down, panned by `pan` (+-90 deg while docking).
/// Where the thesis is silent: the unit sits on top of the front end of the 1.70 m vehicle,
/// 0.70 m ahead of the body origin (taken at the vehicle's centre); noise 4 mm + 0.4 % of the
/// range (1 sigma), the order of a ToF camera's datasheet repeatability.
DepthCameraParams sick_3vistor_t(double pan);

/// The Intel RealSense R200 depth stream at the rear [Stacker thesis, Table 4.2, section 4.2.4]:
/// 640 x 480 px, 59 x 46 deg, looking backwards between the forks. Where the thesis is silent:
/// 0.5-3.5 m (Intel's indoor range), optical centre 0.50 m above the floor at the rear end
/// 0.85 m behind the body origin, tilted 10 deg down so that the pockets of a pallet on the floor
/// or on the 0.30 m limiter stay in view from 1.0 m, and stereo noise 1 mm + 0.3 % per metre of
/// range squared (1 sigma).
DepthCameraParams realsense_r200();

/// A depth camera rendered by ray casting the scene. A pixel's noise is drawn from the seed given
/// at construction, the frame's number and the pixel's index, so a run is reproducible and a pixel
/// reads the same whichever window of the frame is rendered. Not thread-safe (frames are counted).
class DepthCamera {
 public:
  DepthCamera(DepthCameraParams params, std::uint64_t seed);

  const DepthCameraParams& params() const { return params_; }
  const perception::DepthCameraModel& model() const { return params_.model; }
  /// Turns the pan-tilt unit.
  void set_pan_tilt(double pan, double tilt);

  /// The depth image seen from a robot at `robot_pose` on the floor of `scene`. With a `window`
  /// only its pixels are cast and the rest of the image has no return: a detector that reads a
  /// region of interest costs what that region costs.
  perception::DepthImage render(const DepthScene& scene, const geometry::Pose2& robot_pose,
                                const std::optional<perception::PixelWindow>& window = std::nullopt);
  /// The same without noise.
  perception::DepthImage render_ideal(const DepthScene& scene, const geometry::Pose2& robot_pose) const;

 private:
  perception::DepthImage render_impl(const DepthScene& scene, const geometry::Pose2& robot_pose,
                                     const perception::PixelWindow& window,
                                     std::optional<std::uint64_t> frame_key) const;

  DepthCameraParams params_;
  std::uint64_t seed_;
  std::uint64_t frames_ = 0;
};

}  // namespace fleet::sim
