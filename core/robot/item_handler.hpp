#pragma once

#include "map/site.hpp"
#include "robot/order_reporter.hpp"
#include "task/task_executor.hpp"

namespace fleet::robot {

/// A tool that handles items at an order's stops while the forklift software stands there (task
/// states PICK_ITEMS and DROP_ITEMS): the picker's arm (robot/picker/picker_arm_stops.hpp). The
/// forklift software plugs one in when its type has one; without one it refuses pick orders.
class ItemHandler {
 public:
  virtual ~ItemHandler() = default;
  /// One control step at sim time `t`: starts, times and ends the work at the stop `executor`
  /// stands at and answers it (TaskExecutor::items_done), telling people what it does on
  /// `reports`; does nothing in any other state.
  virtual void step(double t, task::TaskExecutor& executor, const map::Site& site, OrderReporter& reports) = 0;

  /// On a loader walk (docs/loader.md): the stop it stands at (-1 while it drives), and the boxes
  /// set on transporters' pallets in the order under way.
  struct LoaderProgress {
    int walk_stop = -1;
    int boxes_loaded = 0;
  };
  virtual LoaderProgress loader_progress() const { return {}; }
};

}  // namespace fleet::robot
