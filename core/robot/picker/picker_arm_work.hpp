#pragma once
// What the picker's arm does while the base stands beside a place: the boxes of a pick line
// located with the boom camera, picked and stowed on the base's tray; at the drop place taken
// from the tray and put down on the pallet [Picker thesis, section 4.4, Algorithm 4].

#include <cstdint>
#include <string>
#include <vector>

#include "arm/pick_motion.hpp"
#include "geometry/pose.hpp"
#include "map/site.hpp"
#include "perception/box_marker_camera.hpp"

namespace fleet::robot {

/// Where boxes stand relative to the base parked side-on beside a place (the place on its left).
struct PickerArmLayout {
  /// From the base's centre to the near edge of the pallet, to the left, m: the item standoff
  /// (1.0 m) less half an EPAL's length (0.6 m).
  double pallet_edge_y = 0.40;
  double pallet_top = 0.144;  ///< EPAL height, m
  /// Boxes are taken along the pallet's near edge, one slot after the other, this far apart
  /// along the base, m; the rest of the pallet's layout is not modelled.
  double slot_pitch = 0.35;
  int slots = 3;  ///< in front of the arm first, then ahead of it, then behind
  /// Out of the arm's reach, the base slides along the pallet to bring the box in front of the
  /// arm, at this speed [Picker thesis, section 5.3.3.1.2: the arm asks navigation to move].
  double slide_speed = 0.3;  ///< m/s, the thesis's test speed
  /// The tray over the rear of the base the boxes ride on, one beside the other: each slot's
  /// bottom centre, base frame, m. Stacked, they would come too near the arm's base column for
  /// the joint limits of [Picker thesis, Table 10]; so a tour carries as many boxes as it has slots.
  std::vector<Eigen::Vector3d> tray{{-0.25, 0.15, 0.40}, {-0.25, -0.15, 0.40}};
  /// Boxes set one on the other at each tray slot: 1 on the base's own tray.
  int tray_layers = 1;
  /// Where a loader sets boxes on the pallet of the transporter behind it, its near edge just
  /// behind the base (orders::transporter_pose): the row the arm reaches, 0.55 m behind the base's
  /// centre, three across (pick-eval's loader deck), the pallet's top raised to 0.30 m (forks at
  /// 0.156 m under an EPAL).
  std::vector<Eigen::Vector3d> deck{{-0.55, 0.25, 0.30}, {-0.55, -0.25, 0.30}, {-0.55, 0.0, 0.30}};
  /// Layers of the deck row: each box of the next layer is set on the one below it, so a pallet
  /// takes deck.size() x deck_layers boxes (orders::LoaderLayout::pallet_boxes). Behind the base
  /// the UR5 sets a box's bottom at 0.2 to 0.6 m within the joint limits of [Picker thesis,
  /// Table 10]: two layers of the plant's boxes (at most 0.30 m high) on a pallet at 0.30 m.
  int deck_layers = 2;
};

/// The arm's time for one stop, or why it cannot work there.
struct ArmWork {
  bool ok = false;
  std::string reason;
  double duration = 0.0;  ///< s: every locate, pick, stow (or unstow and drop) of the stop
  int boxes = 0;
};

/// Plans the arm's work at a stop and times it; the boxes are located by the simulated boom
/// camera from their true places, with its noise.
class PickerArmWork {
 public:
  PickerArmWork(arm::PickMotionPlanner planner, perception::DepthMarkerCameraParams camera, PickerArmLayout layout,
                std::uint64_t seed);

  /// `quantity` boxes of `stock` picked off the pallet on the left and set on the tray's free
  /// slots, after the boxes `tray` holds already; they are added to it. Refused when the tray
  /// has not that many free slots.
  ArmWork pick(const map::BoxStock& stock, int quantity, std::vector<map::BoxStock>& tray);
  /// One box of `stock` picked as pick() picks each, from any place of the pallet: position
  /// `position` along its near edge (slot position % slots, the order pick() and drop() fill them
  /// in) and `layer` boxes up; set on the tray's next free slot and added to it.
  ArmWork pick_at(const map::BoxStock& stock, int position, int layer, std::vector<map::BoxStock>& tray);
  /// Every box of `tray` taken off it, the last set first, and put down on the pallet on the left, which
  /// holds `on_pallet` boxes already (side by side along its near edge, then a layer up).
  ArmWork drop(const std::vector<map::BoxStock>& tray, int on_pallet);

  const PickerArmLayout& layout() const { return layout_; }

 private:
  /// The box's top-face marker in the base frame, at slot `k` of the pallet's near edge, `layer`
  /// boxes up.
  perception::BoxMarker marker_at(const map::BoxStock& stock, int k, int layer) const;
  /// Where the base tries to stand for a box `box_x` along the pallet from the arm, in order:
  /// (along the pallet, away from it) from where it stopped, m.
  std::vector<Eigen::Vector2d> base_moves(double box_x) const;
  /// Why the tray cannot take `quantity` boxes more; empty when it can.
  std::string tray_refusal(int quantity, const std::vector<map::BoxStock>& tray) const;
  /// The box whose marker is `truth` located (the base sliding along the pallet when the arm cannot reach it),
  /// picked and stowed on the tray; its times added to `work` and the camera's clock `t`. False with
  /// `work.reason` set when it could not be.
  bool pick_box(const map::BoxStock& stock, const perception::BoxMarker& truth, std::vector<map::BoxStock>& tray,
                double& t, ArmWork& work);
  /// Where the box `index` of `tray` stands: its slot's bottom centre (slot index % slots), on
  /// the boxes set at that slot before it, base frame.
  Eigen::Vector3d tray_bottom(const std::vector<map::BoxStock>& tray, std::size_t index) const;

  arm::PickMotionPlanner planner_;
  perception::DepthMarkerCamera camera_;
  /// The boom camera's clock, s: it runs on from one stop to the next (the camera takes its
  /// frames at its rate on one clock, whatever the stop).
  double camera_time_ = 0.0;
  PickerArmLayout layout_;
};

/// The box a place's stock holds, as the arm's plans take it: mass and size.
arm::Box box_of(const map::BoxStock& stock);

/// The picker's arm work as the robot builds it (robot_type picker): the UR5 with its vacuum gripper
/// [Picker thesis, sections 3.1-3.2], the boom camera and layout of its configuration
/// (PickerConfig::box_camera, PickerConfig::arm_layout).
PickerArmWork make_picker_arm_work(const perception::DepthMarkerCameraParams& camera, const PickerArmLayout& layout,
                                   std::uint64_t seed);

}  // namespace fleet::robot
