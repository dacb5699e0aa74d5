#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "robot/item_handler.hpp"
#include "robot/picker/picker_arm_work.hpp"

namespace fleet::robot {

/// The picker's arm at the stops of a pick tour [Picker thesis, section 4.4]: at a rack place it
/// plans and times the arm's picks of the line's boxes onto the tray (PickerArmWork::pick), at
/// the packing place it puts the tray's boxes down; the base stands for the summed time of the
/// moves, then the stop is answered.
class PickerArmStops : public ItemHandler {
 public:
  explicit PickerArmStops(PickerArmWork arm) : arm_(std::move(arm)) {}
  void step(double t, task::TaskExecutor& executor, const map::Site& site, OrderReporter& reports) override;

 private:
  PickerArmWork arm_;
  std::vector<map::BoxStock> tray_;  ///< the boxes on the picker's tray, bottom first
  std::optional<double> done_at_;    ///< sim time the arm's work at this stop ends
};

}  // namespace fleet::robot
