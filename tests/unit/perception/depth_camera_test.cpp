#include "sim/depth_camera.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <numbers>

#include "geometry/pose.hpp"

using fleet::geometry::Pose2;
using fleet::perception::DepthCameraModel;
using fleet::perception::DepthImage;
using fleet::perception::Vec3;
using namespace fleet::sim;

namespace {

using ::fleet::geometry::kDeg;

// A level camera with a narrow view, its optical centre `height` above the floor at the body
// origin, looking along +x.
DepthCameraParams level_camera(double height) {
  DepthCameraParams p;
  p.model = {201, 41, 60.0 * kDeg, 12.0 * kDeg, 0.1, 10.0, {0.0, 0.0, height, 0.0, 0.0}};
  return p;
}

float centre_depth(const DepthImage& image) {
  return image.at(image.width / 2, image.height / 2);
}

// The column whose pixel centre ray points at lateral offset `y` at distance `x`, for a camera
// at the body origin looking along +x (y to the left).
int column_towards(const DepthCameraModel& m, double x, double y) {
  return static_cast<int>(std::floor(0.5 * m.width - m.fx() * y / x));
}

}  // namespace

TEST(RayBox, SlabMethodFindsTheEntryDistanceAndMisses) {
  const Box3 box{{1.0, -0.5, 0.0}, {2.0, 0.5, 1.0}};
  const Vec3 origin{0.0, 0.0, 0.5};
  EXPECT_NEAR(ray_box(origin, {1.0, 1e30, 1e30}, box, 0.0, 100.0), 1.0, 1e-12);
  // 45 degrees to the left: enters through the x = 1 face at y = 1 > 0.5, so misses.
  EXPECT_LT(ray_box(origin, {1.0, 1.0, 1e30}, box, 0.0, 100.0), 0.0);
  // Stopped short of the box.
  EXPECT_LT(ray_box(origin, {1.0, 1e30, 1e30}, box, 0.0, 0.9), 0.0);
}

TEST(DepthCamera, HitsTheNearestBoxOfARotatedObjectAtTheRightDepth) {
  DepthScene scene;
  scene.floor = false;
  // A wall 2 m ahead and a thin post in front of it, the post turned 90 deg about its centre.
  scene.add(Pose2{2.0, 0.0, 0.0}, {Box3{{0.0, -2.0, 0.0}, {0.1, 2.0, 2.0}}});
  scene.add(Pose2{1.5, 0.0, std::numbers::pi / 2}, {Box3{{-0.05, -0.01, 0.0}, {0.05, 0.01, 2.0}}});
  DepthCamera camera(level_camera(1.0), 1);
  const DepthImage image = camera.render_ideal(scene, Pose2{});
  // The post's front face is 1.5 - 0.01 = 1.49 m ahead (turned, its 2 cm side faces the camera).
  EXPECT_NEAR(centre_depth(image), 1.49, 1e-6);
  const int wall_col = column_towards(camera.model(), 2.0, 0.5);
  EXPECT_NEAR(image.at(wall_col, image.height / 2), 2.0, 1e-6);
  // Robot moved 0.5 m back and turned: the same post, 0.5 m farther.
  const DepthImage back = camera.render_ideal(scene, Pose2{-0.5, 0.0, 0.0});
  EXPECT_NEAR(centre_depth(back), 1.99, 1e-6);
}

TEST(DepthCamera, ThePocketsShowALongerRangeThanTheColumns) {
  // A camera at pocket height looking square at the 800 mm face of a pallet 1.5 m ahead.
  DepthScene scene;
  scene.add_pallet(Pose2{1.5 + 0.6, 0.0, std::numbers::pi});
  DepthCamera camera(level_camera(0.06), 1);
  const DepthImage image = camera.render_ideal(scene, Pose2{});
  const int row = image.height / 2;
  const DepthCameraModel& m = camera.model();
  // Columns: outer (y in +-[0.30, 0.40]) and middle (|y| < 0.0725), all on the face.
  for (double y : {0.0, 0.35, -0.35}) EXPECT_NEAR(image.at(column_towards(m, 1.5, y), row), 1.5, 1e-6) << y;
  // Pockets (|y| in [0.0725, 0.30]): a level ray runs down the tunnel until, diverging, it meets
  // a block of the middle or the far row, or leaves through the back.
  for (double y : {0.19, -0.19, 0.10, -0.27}) {
    const float d = image.at(column_towards(m, 1.5, y), row);
    EXPECT_TRUE(std::isnan(d) || d > 1.5 + 0.5) << y;
  }
  // Above the pockets, the cross board closes the face.
  DepthCamera high(level_camera(0.11), 1);
  const DepthImage board = high.render_ideal(scene, Pose2{});
  EXPECT_NEAR(board.at(column_towards(m, 1.5, 0.19), board.height / 2), 1.5, 1e-6);
}

TEST(DepthCamera, PixelPointsLieOnTheSurfaceTheyHit) {
  DepthScene scene;
  DepthCamera camera(sick_3vistor_t(std::numbers::pi / 2), 1);
  const Pose2 robot{0.0, 0.0, 0.0};
  const DepthImage image = camera.render_ideal(scene, robot);
  int checked = 0;
  for (int row = 0; row < image.height; row += 7) {
    for (int col = 0; col < image.width; col += 7) {
      const auto p = fleet::perception::pixel_point(camera.model(), image, col, row);
      if (!p) continue;
      EXPECT_NEAR(p->z, 0.0, 1e-5);  // the floor
      EXPECT_GT(p->y, 0.0);          // panned to the left
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
}

TEST(DepthCamera, RangeNoiseHasTheConfiguredSigmaAndIsReproducible) {
  DepthScene scene;
  scene.floor = false;
  scene.add(Pose2{2.0, 0.0, 0.0}, {Box3{{0.0, -5.0, -5.0}, {0.1, 5.0, 5.0}}});
  DepthCameraParams p = level_camera(1.0);
  p.noise = {0.002, 0.003, 0.001};
  DepthCamera camera(p, 7);
  const DepthImage ideal = camera.render_ideal(scene, Pose2{});
  const DepthImage noisy = camera.render(scene, Pose2{});
  double sum = 0.0, sq = 0.0;
  int n = 0;
  for (int row = 0; row < ideal.height; ++row) {
    for (int col = 0; col < ideal.width; ++col) {
      // Normalised by the sigma of this pixel's range, the error is a unit normal.
      const Vec3 ray =
          fleet::perception::pixel_ray(p.model, fleet::perception::camera_axes(p.model.mount), col + 0.5, row + 0.5);
      const double range = ideal.at(col, row) * fleet::perception::norm(ray);
      const double e = (noisy.at(col, row) - ideal.at(col, row)) * fleet::perception::norm(ray) / p.noise.sigma(range);
      sum += e;
      sq += e * e;
      ++n;
    }
  }
  EXPECT_NEAR(sum / n, 0.0, 0.03);
  EXPECT_NEAR(std::sqrt(sq / n), 1.0, 0.03);
  DepthCamera again(p, 7);
  EXPECT_EQ(again.render(scene, Pose2{}).depth, noisy.depth);
}

TEST(DepthCamera, ReturnsOutsideTheWorkingRangeAreDropped) {
  DepthScene scene;
  scene.floor = false;
  scene.add(Pose2{0.3, 0.0, 0.0}, {Box3{{0.0, -5.0, -5.0}, {0.1, 5.0, 5.0}}});
  DepthCamera camera(realsense_r200(), 1);
  camera.set_pan_tilt(0.0, 0.0);
  // The wall is 0.3 + 0.85 = 1.15 m ahead of the rear camera turned forwards: in range.
  EXPECT_NEAR(centre_depth(camera.render_ideal(scene, Pose2{})), 1.15, 1e-6);
  // Robot moved to 0.2 m from the wall: below the R200's 0.5 m minimum.
  EXPECT_TRUE(std::isnan(centre_depth(camera.render_ideal(scene, Pose2{0.95, 0.0, 0.0}))));
}

TEST(DepthCamera, PresetsFollowTheThesisTables) {
  const DepthCameraParams tof = sick_3vistor_t(std::numbers::pi / 2);
  EXPECT_EQ(tof.model.width, 176);
  EXPECT_EQ(tof.model.height, 144);
  EXPECT_NEAR(tof.model.hfov, 69.0 * kDeg, 1e-12);
  EXPECT_NEAR(tof.model.mount.z, 1.64, 1e-12);
  EXPECT_NEAR(tof.model.mount.tilt, -50.0 * kDeg, 1e-12);
  const DepthCameraParams rs = realsense_r200();
  EXPECT_EQ(rs.model.width, 640);
  EXPECT_EQ(rs.model.height, 480);
  EXPECT_NEAR(rs.model.vfov, 46.0 * kDeg, 1e-12);
  EXPECT_NEAR(rs.model.mount.pan, std::numbers::pi, 1e-12);
}

TEST(DepthCamera, AFullRealSenseFrameRendersQuickly) {
  // Not a benchmark: a generous bound that only catches a lost bounding-box test.
  DepthScene scene;
  scene.add_limiter(Pose2{-3.5, 0.0, std::numbers::pi / 2}, 20.0, 1.2);
  for (int i = -4; i <= 4; ++i) scene.add_pallet(Pose2{-3.5, i * 0.95, std::numbers::pi}, 0.30);
  DepthCamera camera(realsense_r200(), 3);
  const auto start = std::chrono::steady_clock::now();
  const DepthImage image = camera.render(scene, Pose2{});
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(image.depth.size(), 640u * 480u);
  EXPECT_LT(ms, 200.0);
  RecordProperty("render_ms", std::to_string(ms));
}
