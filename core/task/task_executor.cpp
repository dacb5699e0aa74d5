#include "task/task_executor.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fleet::task {

using geometry::Pose2;

const char* to_string(PlanPurpose p) {
  switch (p) {
    case PlanPurpose::kToPick:
      return "to_pick";
    case PlanPurpose::kToDrop:
      return "to_drop";
    case PlanPurpose::kHome:
      return "home";
    case PlanPurpose::kToPlace:
      return "to_place";
  }
  return "unknown";
}

const char* to_string(TaskReport::Kind k) {
  switch (k) {
    case TaskReport::Kind::kAccepted:
      return "accepted";
    case TaskReport::Kind::kPicked:
      return "picked";
    case TaskReport::Kind::kAreaEmpty:
      return "area_empty";
    case TaskReport::Kind::kDropped:
      return "dropped";
    case TaskReport::Kind::kCancelled:
      return "cancelled";
    case TaskReport::Kind::kFailed:
      return "failed";
    case TaskReport::Kind::kHomeReached:
      return "home_reached";
    case TaskReport::Kind::kArrived:
      return "arrived";
  }
  return "unknown";
}

TaskExecutor::TaskExecutor(ExecutorParams params, Pose2 home)
    : params_(params),
      home_(home),
      follower_(params.follower),
      search_(params.search, params.geometry),
      pick_(params.pick, params.geometry),
      place_(params.place, params.geometry) {}

bool TaskExecutor::submit(const TaskOrder& order, std::string* why) {
  if (order_ && order_->loader && order.loader && order.order_id == order_->order_id) {
    // An update (VDA 5050 style): the walk stays, more of it is released.
    order_->released = order.released;
    order_->approach = order.approach;
    order_->pallet = order.pallet;
    return true;
  }
  waiting_for_release_ = false;
  release_wait_home_ = false;
  loaded_pallet_ = 0;
  if (!machine_.accepts_orders()) {
    if (why) *why = std::string("order not accepted in ") + to_string(machine_.state());
    return false;
  }
  if (order.kind == orders::OrderKind::kPick && order.items.empty()) {
    if (why) *why = "a pick order names no items";
    return false;
  }
  order_ = order;
  item_line_ = 0;
  const Transition tr = fire(order.kind == orders::OrderKind::kMove ? Event::kMoveOrder : Event::kOrder);
  if (!tr.accepted) order_.reset();
  if (!tr.accepted && why) *why = tr.reason;
  return tr.accepted;
}

bool TaskExecutor::set_drop(const std::string& area_id, const Pose2& area) {
  if (!order_ || order_->kind != orders::OrderKind::kTransport || !order_->drop_area_id.empty() || area_id.empty()) {
    return false;
  }
  order_->drop_area_id = area_id;
  order_->drop_area = area;
  if (machine_.phase() == orders::OrderPhase::kToDrop) request_plan(PlanPurpose::kToDrop);
  return true;
}

Pose2 TaskExecutor::item_pose(const Pose2& place) const {
  const double toward_road = place.yaw;
  return {place.x + params_.item_standoff * std::cos(toward_road),
          place.y + params_.item_standoff * std::sin(toward_road),
          geometry::normalize_angle(toward_road + std::numbers::pi / 2.0)};
}

Pose2 TaskExecutor::goal_for(PlanPurpose purpose) const {
  // Paths end on the road in front of the area; search and place take it from there. A pick
  // order's end beside the place, where the arm reaches it.
  const bool items = order_ && order_->kind == orders::OrderKind::kPick;
  switch (purpose) {
    case PlanPurpose::kToPick:
      if (items) return item_pose(order_->items.at(std::min(item_line_, order_->items.size() - 1)).place);
      return control::PalletSearch::search_pose(order_->pick_area, params_.search.standoff);
    case PlanPurpose::kToDrop:
      if (items) return item_pose(order_->drop_area);
      return control::PalletSearch::search_pose(order_->drop_area, params_.search.standoff);
    case PlanPurpose::kHome:
      return home_;
    case PlanPurpose::kToPlace:
      return order_->drop_area;
  }
  return home_;
}

void TaskExecutor::request_plan(PlanPurpose purpose) {
  if (purpose == PlanPurpose::kToDrop && order_ && order_->drop_area_id.empty()) {
    // No drop place yet (set_drop): stand with the load, no path.
    pending_request_.reset();
    active_purpose_ = purpose;
    have_path_ = false;
    follower_.clear();
    return;
  }
  PlanRequest req;
  req.id = next_request_id_++;
  req.purpose = purpose;
  req.goal = goal_for(purpose);
  pending_request_ = req;
  active_request_id_ = req.id;
  active_purpose_ = purpose;
  have_path_ = false;
  last_request_time_ = now_;
  follower_.clear();
}

bool TaskExecutor::waits_in_place() const {
  return item_line_ > 0 && order_->pallet != 0 && order_->pallet == loaded_pallet_;
}

void TaskExecutor::hold_for_release() {
  waiting_for_release_ = true;
  release_wait_home_ = !waits_in_place();
  if (release_wait_home_) {
    request_plan(PlanPurpose::kHome);
    if (blocked_) fire(Event::kBlocked);
    return;
  }
  pending_request_.reset();
  active_request_id_ = 0;
  active_purpose_ = PlanPurpose::kToPick;
  have_path_ = false;
  follower_.clear();
  fire(Event::kBlocked);
}

bool TaskExecutor::stop_open() const {
  return item_line_ < order_->released || item_line_ < order_->approach;
}

void TaskExecutor::follow_release() {
  if (!order_ || !order_->loader) return;
  const State s = machine_.state();
  if (s == State::kPickItems) {
    // At a stop it drove to before its release, which the server took back: its transporter was
    // replaced, and the new one comes in behind the stop, past where the loader stands.
    if (!stop_open() && !waits_in_place())
      fire(Event::kStopWithdrawn, "its transporter changed before the stop was released");
    return;
  }
  if (s != State::kTrackPath && s != State::kWaiting) return;
  if (!waiting_for_release_) {
    // On its way to a stop ahead of its release, which the server took back.
    if (active_purpose_ == PlanPurpose::kToPick && !stop_open()) hold_for_release();
    return;
  }
  if (stop_open()) {
    waiting_for_release_ = false;
    release_wait_home_ = false;
    request_plan(PlanPurpose::kToPick);
    if (s == State::kTrackPath && blocked_) fire(Event::kBlocked);
  } else if (!release_wait_home_ && !waits_in_place()) {
    release_wait_home_ = true;
    request_plan(PlanPurpose::kHome);
  }
}

void TaskExecutor::report(TaskReport::Kind kind, const std::string& area, const std::string& detail) {
  TaskReport r;
  r.kind = kind;
  r.order_id = order_ ? order_->order_id : std::string{};
  r.area_id = area;
  r.detail = detail;
  reports_.push_back(std::move(r));
}

void TaskExecutor::end_order(TaskReport::Kind kind, const std::string& area, const std::string& detail) {
  report(kind, area, detail);
  waiting_for_release_ = false;
  order_.reset();
  request_plan(PlanPurpose::kHome);
}

Transition TaskExecutor::fire(Event e, const std::string& reason) {
  Transition tr = machine_.handle(e, reason);
  if (tr.accepted) {
    transitions_.push_back(tr);
    apply(tr);
  }
  return tr;
}

void TaskExecutor::apply(const Transition& tr) {
  switch (tr.effect) {
    case Effect::kPlanToPick:
      search_.stop();
      pick_.stop();
      place_.stop();
      pick_attempts_ = 0;
      waiting_for_plan_ = false;
      // A pick order comes back here for each of its lines; it was accepted once.
      if (item_line_ == 0) report(TaskReport::Kind::kAccepted, order_->pick_area_id);
      if (order_->loader && !stop_open()) {
        hold_for_release();
        break;
      }
      request_plan(PlanPurpose::kToPick);
      // Taken while waiting for traffic on the way home: wait on until the road is granted.
      if (blocked_) fire(Event::kBlocked);
      break;
    case Effect::kPlanToPlace:
      waiting_for_plan_ = false;
      report(TaskReport::Kind::kAccepted, order_->drop_area_id);
      request_plan(PlanPurpose::kToPlace);
      if (blocked_) fire(Event::kBlocked);
      break;
    case Effect::kFinishMove:
      // Parked at the place, which is home from now on: later orders end here.
      follower_.clear();
      home_ = order_->drop_area;
      report(TaskReport::Kind::kArrived, order_->drop_area_id);
      order_.reset();
      break;
    case Effect::kStartSearch:
      follower_.clear();
      pick_.stop();
      search_.start(order_->pick_area);
      break;
    case Effect::kStartPick:
      pick_.start(search_.marker_id(), now_);
      break;
    case Effect::kPlanToDrop:
      report(TaskReport::Kind::kPicked, order_->pick_area_id);
      request_plan(PlanPurpose::kToDrop);
      break;
    case Effect::kStartDrop:
      follower_.clear();
      place_.start(order_->drop_area, now_);
      break;
    case Effect::kReportEmpty:
      search_.stop();
      end_order(TaskReport::Kind::kAreaEmpty, order_->pick_area_id, search_.empty_reason());
      break;
    case Effect::kFinishOrder:
      place_.stop();
      end_order(TaskReport::Kind::kDropped, order_->drop_area_id);
      break;
    case Effect::kAbandonPick:
      pick_.stop();
      search_.stop();
      end_order(TaskReport::Kind::kFailed, order_->pick_area_id, tr.reason);
      break;
    case Effect::kCancelOrder:
      search_.stop();
      end_order(TaskReport::Kind::kCancelled, order_ ? order_->pick_area_id : std::string{});
      break;
    case Effect::kStop:
      follower_.clear();
      report(TaskReport::Kind::kHomeReached, {});
      break;
    case Effect::kFail:
      follower_.clear();
      search_.stop();
      pick_.stop();
      place_.stop();
      report(TaskReport::Kind::kFailed, {}, machine_.error_reason());
      waiting_for_release_ = false;
      order_.reset();
      pending_request_.reset();
      active_request_id_ = 0;
      break;
    case Effect::kRestore:
      // Back from PAUSED in the middle of a manoeuvre: its clocks ran on during the pause, so a
      // camera-driven alignment or a placement restarts from where the robot stands rather than
      // fail on a stale timer. Driving in, lifting, lowering and backing out go on as they were.
      if (machine_.state() == State::kPickPallet && pick_.status() == control::PickStatus::kAligning) {
        pick_.start(search_.marker_id(), now_);
      } else if (machine_.state() == State::kDropPallet && place_.status() <= control::PlaceStatus::kSettling &&
                 order_) {
        place_.start(order_->drop_area, now_);
      }
      // Back from WAITING or PAUSED: if the blockage is still there, wait again.
      if ((blocked_ || waiting_for_plan_ || stands_for_release()) &&
          (machine_.state() == State::kTrackPath || machine_.state() == State::kGoHome)) {
        fire(Event::kBlocked);
      } else if (machine_.state() == State::kWaiting && !blocked_ && !waiting_for_plan_ && !stands_for_release()) {
        // Paused while waiting, and what it waited for (a grant, a clear road, a plan) came
        // during the pause: set_blocked and path_received only unblock a robot in WAITING, so
        // the resume must, or the robot stands on a road the traffic manager granted it.
        fire(Event::kUnblocked);
      }
      break;
    case Effect::kStartItems:
      // The base stands; the owner's arm works and answers with items_done().
      follower_.clear();
      break;
    case Effect::kNone:
    case Effect::kSuspend:
    case Effect::kClear:
      break;
  }
}

void TaskExecutor::items_done(bool ok, const std::string& reason) {
  const State s = machine_.state();
  if (s != State::kPickItems && s != State::kDropItems) return;
  if (!ok) {
    fire(Event::kItemsFailed, reason.empty() ? std::string("the arm failed") : reason);
  } else if (s == State::kDropItems) {
    fire(Event::kItemsDropped);
  } else {
    if (order_->loader) loaded_pallet_ = order_->pallet;
    ++item_line_;
    const bool last = item_line_ >= order_->items.size();
    fire(!last ? Event::kItemsPicked : order_->loader ? Event::kWalkLoaded : Event::kTourPicked);
  }
}

void TaskExecutor::path_received(std::uint64_t request_id, std::vector<Pose2> path) {
  if (request_id != active_request_id_ || request_id == 0) return;
  if (path.empty()) {
    plan_failed(request_id);
    return;
  }
  if (path.size() >= 2) {
    // Finish the road path with the heading of its last leg: the search or the place manoeuvre
    // turns towards the area itself, and the way home ends in the home heading.
    const auto& a = path[path.size() - 2];
    auto& b = path.back();
    const bool side_on = order_ && order_->kind == orders::OrderKind::kPick &&
                         (active_purpose_ == PlanPurpose::kToPick || active_purpose_ == PlanPurpose::kToDrop);
    if (active_purpose_ == PlanPurpose::kHome || active_purpose_ == PlanPurpose::kToPlace || side_on) {
      b.yaw = goal_for(active_purpose_).yaw;
    } else if (geometry::distance(a.position(), b.position()) > 1e-6) {
      b.yaw = std::atan2(b.y - a.y, b.x - a.x);
    }
  }
  // Home is often a stall between others: the robot backs in rather than turn round in it.
  follower_.set_path(std::move(path), active_purpose_ == PlanPurpose::kHome);
  have_path_ = true;
  waiting_for_plan_ = false;
  if (machine_.state() == State::kWaiting && !blocked_) fire(Event::kUnblocked);
}

void TaskExecutor::plan_failed(std::uint64_t request_id) {
  if (request_id != active_request_id_ || request_id == 0) return;
  waiting_for_plan_ = true;
  have_path_ = false;
  follower_.clear();
  if (machine_.state() == State::kTrackPath || machine_.state() == State::kGoHome) fire(Event::kBlocked);
}

void TaskExecutor::set_blocked(bool blocked) {
  blocked_ = blocked;
  if (blocked && (machine_.state() == State::kTrackPath || machine_.state() == State::kGoHome)) {
    fire(Event::kBlocked);
  } else if (!blocked && machine_.state() == State::kWaiting && !waiting_for_plan_ && !stands_for_release()) {
    fire(Event::kUnblocked);
  }
}

void TaskExecutor::replan() {
  const State s = machine_.state();
  // Waiting counts too, whether for a plan or on a blocked road: the new plan may lead around.
  // Not a loader standing for its release: it has nowhere to go yet.
  if (stands_for_release()) return;
  if (s == State::kTrackPath || s == State::kGoHome || s == State::kWaiting) {
    request_plan(active_purpose_);
  }
}

bool TaskExecutor::pause() {
  return fire(Event::kPause).accepted;
}
bool TaskExecutor::resume() {
  return fire(Event::kResume).accepted;
}

bool TaskExecutor::cancel(std::string* why) {
  const Transition tr = fire(Event::kCancel);
  if (!tr.accepted && why) *why = tr.reason;
  return tr.accepted;
}

void TaskExecutor::fault(const std::string& reason) {
  fire(Event::kFault, reason);
}
bool TaskExecutor::reset() {
  return fire(Event::kReset).accepted;
}

std::optional<PlanRequest> TaskExecutor::take_plan_request() {
  std::optional<PlanRequest> r = pending_request_;
  pending_request_.reset();
  return r;
}

std::vector<Transition> TaskExecutor::take_transitions() {
  std::vector<Transition> t;
  t.swap(transitions_);
  return t;
}

std::vector<TaskReport> TaskExecutor::take_reports() {
  std::vector<TaskReport> r;
  r.swap(reports_);
  return r;
}

TaskOutput TaskExecutor::step(const TaskInput& in) {
  const double dt = std::isnan(last_time_) ? 0.0 : std::max(in.time - last_time_, 0.0);
  last_time_ = in.time;
  now_ = in.time;
  TaskOutput out;
  out.fork_up = fork_up_;
  follow_release();

  switch (machine_.state()) {
    case State::kIdle:
    case State::kPaused:
    case State::kError:
    case State::kPickItems:
    case State::kDropItems:
      break;
    case State::kWaiting:
      if (waiting_for_plan_ && !pending_request_ && in.time - last_request_time_ >= params_.replan_interval) {
        request_plan(active_purpose_);
      }
      break;
    case State::kTrackPath:
    case State::kGoHome: {
      if (!have_path_) break;
      out.twist = follower_.step({in.pose, dt, in.obstacle_distance, in.granted_distance});
      if (follower_.arrived()) {
        have_path_ = false;
        if (geometry::distance(in.pose.position(), goal_for(active_purpose_).position()) > params_.arrival_tolerance) {
          // The path ended short of the goal (a route handed over from outside without its leg
          // off the road): the road's end is not the area or home, so plan again from here.
          request_plan(active_purpose_);
          break;
        }
        if (waiting_for_release_) {
          fire(Event::kBlocked);  // home, where it waits for its stop to be released
        } else if (machine_.state() == State::kGoHome) {
          fire(Event::kHomeReached);
        } else {
          fire(order_ && order_->kind == orders::OrderKind::kPick ? Event::kAtItems : Event::kPathEnded);
        }
      }
      break;
    }
    case State::kSearchPallet: {
      out.twist = search_.step(in.pose, in.detections, dt);
      if (search_.status() == control::SearchStatus::kFound) {
        fire(Event::kPalletFound);
      } else if (search_.status() == control::SearchStatus::kEmpty) {
        fire(Event::kAreaEmpty);
      }
      break;
    }
    case State::kPickPallet: {
      const control::ForkCommand fc = pick_.step(in.time, in.detections, dt);
      out.twist = fc.twist;
      fork_up_ = fc.fork_up;
      if (pick_.status() == control::PickStatus::kDone) {
        fire(Event::kPickDone);
      } else if (pick_.status() == control::PickStatus::kFailed) {
        ++pick_attempts_;
        if (pick_attempts_ >= params_.max_pick_attempts) {
          fire(Event::kPickGaveUp,
               std::string("pick failed ") + std::to_string(pick_attempts_) + " times: " + pick_.failure());
        } else {
          fire(Event::kPickFailed);
        }
      }
      break;
    }
    case State::kDropPallet: {
      const control::ForkCommand fc = place_.step(in.time, in.pose, dt);
      out.twist = fc.twist;
      fork_up_ = fc.fork_up;
      if (place_.status() == control::PlaceStatus::kDone) {
        fire(Event::kDropDone);
      } else if (place_.status() == control::PlaceStatus::kFailed) {
        fire(Event::kDropFailed, "placement did not converge");
      }
      break;
    }
  }
  out.fork_up = fork_up_;
  return out;
}

}  // namespace fleet::task
