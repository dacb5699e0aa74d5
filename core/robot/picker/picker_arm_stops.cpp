#include "robot/picker/picker_arm_stops.hpp"

#include <cmath>
#include <string>

#include "model/messages.hpp"

namespace fleet::robot {

void PickerArmStops::step(double t, task::TaskExecutor& executor, const map::Site& site, OrderReporter& reports) {
  const task::State state = executor.state();
  const task::TaskOrder* running = executor.order() ? &*executor.order() : nullptr;
  if (running == nullptr || !running->loader) {
    progress_ = {};
    progress_order_.clear();
  } else if (running->order_id != progress_order_) {
    progress_ = {};
    progress_order_ = running->order_id;
  }
  if (state != task::State::kPickItems && state != task::State::kDropItems) {
    done_at_.reset();
    progress_.walk_stop = -1;
    return;
  }
  const task::TaskOrder& order = *running;
  if (order.loader && state == task::State::kPickItems) {
    progress_.walk_stop = static_cast<int>(executor.item_line());
  }
  if (done_at_) {
    if (t < *done_at_) {
      // Said again each step: the state change that starts the work clears the robot's detail.
      reports.set_detail(work_detail_);
      return;
    }
    done_at_.reset();
    if (state == task::State::kDropItems) tray_.clear();
    if (order.loader && state == task::State::kPickItems) progress_.boxes_loaded += boxes_at_work_;
    executor.items_done(true);
    return;
  }
  ArmWork work;
  if (state == task::State::kPickItems) {
    const task::ItemStop& stop = order.items.at(executor.item_line());
    const map::LoadingArea* area = site.find_area(stop.place_id);
    if (area == nullptr || !area->boxes) {
      executor.items_done(false, "place " + stop.place_id + " holds no boxes");
      return;
    }
    if (order.loader && executor.item_line() >= order.released) {
      reports.set_detail(model::kDetailWaitsForTransporter);
      return;
    }
    if (order.loader && order.pallet != deck_pallet_) {
      deck_.clear();  // a new transporter moved up: its pallet is empty
      deck_pallet_ = order.pallet;
    }
    work = order.loader ? deck_arm_.pick(*area->boxes, stop.quantity, deck_)
                        : arm_.pick(*area->boxes, stop.quantity, tray_);
  } else {
    work = arm_.drop(tray_, 0);
  }
  if (!work.ok) {
    executor.items_done(false, work.reason);
    return;
  }
  done_at_ = t + work.duration;
  boxes_at_work_ = work.boxes;
  work_detail_ = (state == task::State::kPickItems ? "arm picks " : "arm puts down ") + std::to_string(work.boxes) +
                 " box" + (work.boxes == 1 ? "" : "es") + " in " +
                 std::to_string(static_cast<int>(std::lround(work.duration))) + " s";
  reports.set_detail(work_detail_);
}

}  // namespace fleet::robot
