#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "perception/marker_camera.hpp"

namespace fleet::perception {

/// A pallet as the simulation knows it: where it really is, whatever any robot believes.
struct SimPallet {
  int id = 0;            ///< also the id of its marker
  geometry::Pose2 pose;  ///< centre; yaw points out of the marker face
  bool carried = false;
  geometry::Pose2 offset;  ///< pose in the carrier's body frame while carried
};

struct PalletWorldParams {
  double carry_x = 0.17;        ///< pallet centre on seated forks, metres ahead of the body centre
  double marker_offset = 0.04;  ///< marker centre ahead of the pallet centre along its yaw, metres
  /// Forks rising under a pallet lift it only if it sits this close to the seated position; a
  /// worse approach pushes the pallet or misses its pockets.
  double lift_lateral_tol = 0.02;  ///< metres, sideways
  double lift_depth_tol = 0.03;    ///< metres, along the forks
  double lift_yaw_tol = 0.15;      ///< rad between the forks and the pallet's pockets
};

/// Outcome of one fork movement.
struct ForkEvent {
  enum class Kind { kNone, kLifted, kLiftMissed, kPutDown };
  Kind kind = Kind::kNone;
  int pallet_id = -1;
  geometry::Pose2 offset;  ///< kLifted: the pallet's pose on the forks (the pick error)
};

/// The true pallets of a simulated site and what forks do to them. A pallet stays exactly where
/// it was put down, so a sloppy drop makes the next pick from that area harder.
class PalletWorld {
 public:
  explicit PalletWorld(PalletWorldParams params = {}) : params_(params) {}

  int add(const geometry::Pose2& pose);
  /// Puts the pallet with this id standing at `pose` (adds it, or moves it). Used when the truth
  /// lives elsewhere: an agent mirrors the pallets its server owns. A pallet on these forks is
  /// left alone: false.
  bool place(int id, const geometry::Pose2& pose);
  /// Removes a standing pallet (another robot carries it away). False when unknown or carried here.
  bool remove(int id);
  /// Markers of the pallets standing on the floor (a carried pallet's marker faces the camera
  /// from too close to decode).
  std::vector<Marker> markers() const;
  /// Advances the forks of the robot at `robot_truth`: rising forks lift a seated pallet, lowering
  /// forks put it down, a carried pallet moves with the robot.
  ForkEvent update(int robot, const geometry::Pose2& robot_truth, bool fork_up);

  const std::vector<SimPallet>& pallets() const { return pallets_; }
  const SimPallet* find(int id) const;
  /// The pallet standing nearest `p` within `radius`, if any.
  const SimPallet* standing_near(geometry::Vec2 p, double radius) const;
  const PalletWorldParams& params() const { return params_; }

 private:
  struct Forks {
    int robot = 0;
    bool up = false;
    int carrying = -1;  ///< index into pallets_
  };
  Forks& forks(int robot);

  PalletWorldParams params_;
  std::vector<SimPallet> pallets_;
  std::vector<Forks> forks_;
};

}  // namespace fleet::perception
