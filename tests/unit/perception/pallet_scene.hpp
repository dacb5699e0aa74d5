#pragma once

#include <numbers>

#include "geometry/pose.hpp"
#include "perception/detection_sweep.hpp"
#include "sim/depth_camera.hpp"

namespace fleet::test {

/// The finished-goods row of [Stacker thesis, sections 4.1.2-4.1.3] around one target pallet:
/// the 0.30 m limiter under the row and the target's neighbours 0.15 m to each side.
struct PalletRow {
  static constexpr double kBase = 0.30;
  static constexpr double kSpacing = 0.95;

  /// A scene with the target pallet at `target` (footprint centre) and its row.
  static sim::DepthScene around(const geometry::Pose2& target, bool neighbours = true, bool limiter = true) {
    sim::DepthScene scene;
    const geometry::Vec2 along{-std::sin(target.yaw), std::cos(target.yaw)};
    if (limiter) scene.add_limiter({target.x, target.y, target.yaw + std::numbers::pi / 2}, 20.0, 1.2, kBase);
    scene.add_pallet(target, limiter ? kBase : 0.0);
    if (neighbours) {
      for (double side : {-1.0, 1.0}) {
        const geometry::Vec2 p = target.position() + side * kSpacing * along;
        scene.add_pallet({p.x, p.y, target.yaw}, limiter ? kBase : 0.0);
      }
    }
    return scene;
  }
};

/// A renderer for the sweep: the camera sees the target pallet in its row from a robot at the
/// origin. Turned by 15 deg, a pallet reaches 14 cm further sideways, so the sweep's row leaves
/// `spacing` - 0.8 m between pallets.
inline perception::PalletFrameRenderer row_renderer(sim::DepthCamera& camera, double spacing = 1.3) {
  return [&camera, spacing](const geometry::Pose2& pallet) {
    // The row stays square to the camera even when the target pallet is turned.
    geometry::Pose2 row = pallet;
    row.yaw = perception::pallet_ahead_of_camera(camera.model(), 1.0, 0.0).yaw;
    sim::DepthScene scene;
    const geometry::Vec2 along{-std::sin(row.yaw), std::cos(row.yaw)};
    scene.add_limiter({row.x, row.y, row.yaw + std::numbers::pi / 2}, 20.0, 1.2, PalletRow::kBase);
    scene.add_pallet(pallet, PalletRow::kBase);
    for (double side : {-1.0, 1.0}) {
      const geometry::Vec2 p = row.position() + side * spacing * along;
      scene.add_pallet({p.x, p.y, row.yaw}, PalletRow::kBase);
    }
    return camera.render(scene, geometry::Pose2{});
  };
}

}  // namespace fleet::test
