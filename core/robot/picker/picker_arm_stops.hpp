#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "robot/item_handler.hpp"
#include "robot/picker/picker_arm_work.hpp"

namespace fleet::robot {

/// The picker's arm at the stops of a pick tour [Picker thesis, section 4.4]: at a rack place it
/// plans and times the arm's picks of the line's boxes onto the tray (PickerArmWork::pick), at
/// the packing place it puts the tray's boxes down; the base stands for the summed time of the
/// moves, then the stop is answered. On a loader order it sets each box on the pallet behind it
/// instead (PickerArmLayout::deck), once the stop is released.
class PickerArmStops : public ItemHandler {
 public:
  /// `deck_arm` plans onto the transporter's pallet: the same arm with the deck as its tray.
  PickerArmStops(PickerArmWork arm, PickerArmWork deck_arm) : arm_(std::move(arm)), deck_arm_(std::move(deck_arm)) {}
  void step(double t, task::TaskExecutor& executor, const map::Site& site, OrderReporter& reports) override;
  LoaderProgress loader_progress() const override { return progress_; }

 private:
  PickerArmWork arm_;
  PickerArmWork deck_arm_;
  std::vector<map::BoxStock> tray_;  ///< the boxes on the picker's tray, bottom first
  std::vector<map::BoxStock> deck_;  ///< the boxes on the transporter's pallet behind it
  int deck_pallet_ = -1;             ///< whose pallet deck_ is (TaskOrder::pallet)
  std::optional<double> done_at_;    ///< sim time the arm's work at this stop ends
  int boxes_at_work_ = 0;            ///< boxes the arm moves in the work that ends at done_at_
  std::string work_detail_;          ///< what the robot's detail says while the arm works
  std::string progress_order_;       ///< the loader order progress_ counts for
  LoaderProgress progress_;
};

}  // namespace fleet::robot
