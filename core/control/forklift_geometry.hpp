#pragma once

namespace fleet::control {

/// Where the camera and the forks are on the forklift, and where the marker is on a pallet.
/// Pick, place and search share it so that "the pallet sits on the forks" means the same to all.
struct ForkliftGeometry {
  double camera_x = 0.12;       ///< optical centre, metres ahead of the body centre (front edge)
  double carry_x = 0.17;        ///< pallet centre when carried, metres ahead of the body centre
  double marker_offset = 0.04;  ///< marker centre, metres from the pallet centre along its yaw

  /// Camera-to-marker distance with the pallet seated on the forks.
  double carried_marker_distance() const { return carry_x - marker_offset - camera_x; }
};

}  // namespace fleet::control
