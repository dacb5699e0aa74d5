// The stacker at a place: docking to a pallet, putting the carried one down, parking in its bay,
// and the forks.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "robot/stacker/stacker.hpp"

namespace fleet::robot {

using geometry::Pose2;
using geometry::Vec2;

namespace {

/// A pose of the true map frame seen from the estimated one: the same pose relative to the
/// vehicle. A camera measures relative to the vehicle; the frame it is put in is the estimate's.
Pose2 reframe(const Pose2& from_vehicle, const Pose2& to_vehicle, const Pose2& pose) {
  return geometry::body_pose_to_map(to_vehicle, geometry::map_pose_to_body(from_vehicle, pose));
}

}  // namespace

Pose2 Stacker::dock_prior() const {
  switch (state_) {
    case StackerState::kToPick:
    case StackerState::kDocking:
    case StackerState::kLifting:
      return order_ ? order_->pick_area : home_;
    case StackerState::kToDrop:
    case StackerState::kPlacing:
    case StackerState::kLowering:
      return order_ ? order_->drop_area : home_;
    default: {
      // A bay is docked to like a pallet place: the pallet that would sit on the forks when the
      // stacker stands at the bay's pose.
      const Pose2 stand = order_ && order_->kind == orders::OrderKind::kMove ? order_->drop_area : home_;
      const double back = 0.5 * (config_.body.geometry.front_x() + config_.body.geometry.fork_tip_x()) -
                          carried_offset(config_.docking, config_.body.geometry);
      const Vec2 p = stand.position() - back * heading_of(stand.yaw);
      return {p.x, p.y, stand.yaw};
    }
  }
}

perception::PalletRow Stacker::pallet_row(const Pose2& place, double base_height) const {
  perception::PalletRow row;
  row.base_height = base_height;
  if (base_height > 0.0)
    row.scene.add_limiter({place.x, place.y, place.yaw + std::numbers::pi / 2}, 20.0, 1.2, base_height);
  for (const auto& [id, pose] : standing_) {
    if (geometry::distance(pose.position(), place.position()) > 6.0) continue;
    // A pallet stands on whatever its place stands on.
    double base = 0.0;
    for (const auto& area : nav_.site().site.loading_areas) {
      if (geometry::distance(area.pose.position(), pose.position()) < 0.5) base = area.height;
    }
    row.scene.add_pallet(pose, base);
  }
  return row;
}

control::DockingParams Stacker::docking_params() const {
  control::DockingParams params = config_.docking;
  params.vehicle = config_.body.geometry;
  params.detection_gate = 0.5 * config_.row_pitch;
  params.place_on_prior = state_ != StackerState::kDocking && state_ != StackerState::kToPick;
  return params;
}

void Stacker::start_docking() {
  const Pose2 prior = dock_prior();
  law_.emplace(docking_params(), prior, estimate_, rng_());
  if (state_ == StackerState::kDocking) {
    double height = 0.0;
    if (const auto* area = nav_.site().site.find_area(order_->pick_area_id)) height = area->height;
    perception::StackerDetectorParams dp = config_.detector;
    dp.area.lateral_half = 0.5 * config_.row_pitch;
    detector_.emplace(config_.body.geometry, pallet_row(prior, height), dp, rng_());
  }
  reports_.set_detail("");
  shown_phase_.reset();
  detected_pallet_.reset();
  work_area_ = sweeps_.docking(*law_, estimate_, prior);
  // Without traffic control nobody holds the area for it: it goes at once.
  area_clear_ = !config_.traffic;
}

DockingView Stacker::docking_view() const {
  if (!law_) return {};
  const auto [target1, target2] = law_->targets();
  // Placing a carried pallet or parking, the cameras look for nothing.
  return {{target1, target2}, detector_ ? detected_pallet_ : std::nullopt};
}

void Stacker::dock() {
  if (!area_clear_) {
    // Standing at the end of its route until traffic holds the manoeuvre's area for it.
    apply({0.0, body_.state().theta_steer});
    return;
  }
  control::DockingInput in;
  in.vehicle = estimate_;
  in.steer_angle = body_.state().theta_steer;
  in.dt = step_period();
  if (detector_) {
    // The cameras look where the law expects the pallet relative to the vehicle; what they find
    // is put in the law's frame by the vehicle's estimate.
    const int frames = detector_->frames();
    const auto seen = (*detector_)(body_.pose(), reframe(estimate_, body_.pose(), law_->pallet_estimate()), time_);
    if (seen) in.pallet_detection = reframe(body_.pose(), estimate_, *seen);
    // Between frames the cameras have not lost it: a detection lasts until a frame finds nothing.
    if (detector_->frames() != frames) detected_pallet_ = in.pallet_detection;
  }
  const control::DockingOutput out = law_->update(in);
  if (out.phase != shown_phase_) {
    // Where a docking stands, for the operator and the agent's log.
    shown_phase_ = out.phase;
    reports_.set_detail(std::string("docking: ") + control::to_string(out.phase));
  }
  if (out.phase == control::DockingPhase::kDone) {
    apply({0.0, body_.state().theta_steer});
    if (state_ == StackerState::kParking && order_) {
      finish_order({RobotEvent::Kind::kDone, order_->order_id, order_->drop_area_id, -1, {}});
    } else if (state_ == StackerState::kParking) {
      reports_.add({RobotEvent::Kind::kHome, "", "", -1, {}});
    }
    fire(StackerEvent::kDocked);
    return;
  }
  if (out.phase == control::DockingPhase::kFailed) {
    apply({0.0, body_.state().theta_steer});
    std::string why = out.failure_reason.empty() ? "docking failed" : out.failure_reason;
    if (state_ == StackerState::kDocking) {
      if (detector_ && detector_->found() == 0) {
        why += " (" + std::to_string(detector_->frames()) + " frames, last: " + detector_->last_reason() + ")";
      }
      const std::string area = order_->pick_area_id;
      finish_order({RobotEvent::Kind::kFailed, order_->order_id, "docking at " + area + ": " + why, -1, {}});
      fire(StackerEvent::kDockFailed);
      return;
    }
    if (++dock_attempts_ < config_.max_dock_attempts) {
      reports_.set_detail("docking again: " + why);
      start_docking();
      return;
    }
    // Standing with the reason shown; the operator (or a withdrawal) takes it from here.
    reports_.set_detail("could not dock after " + std::to_string(dock_attempts_) + " attempts: " + why);
    law_.reset();
    return;
  }
  apply(out.command);
}

void Stacker::start_moving_up() {
  const sim::TricycleGeometry& g = config_.body.geometry;
  const Pose2 target = state_ == StackerState::kStanding ? *order_->stand : order_->drop_area;
  const Pose2 goal = rear_axle_at(target, g);
  back_.emplace(goal, config_.move_up, g.wheelbase, control::goal_ahead(estimate_, goal));
  reports_.set_detail("moving up");
  work_area_ = sweeps_.straight_back(estimate_, goal.position(), goal.yaw);
  // Without traffic control nobody holds the area for it: it goes at once.
  area_clear_ = !config_.traffic;
}

void Stacker::move_up() {
  if (!area_clear_) {
    apply({0.0, body_.state().theta_steer});
    return;
  }
  const sim::TricycleCommand command = back_->update(estimate_, step_period());
  if (!back_->done()) {
    apply(command);
    return;
  }
  apply({0.0, body_.state().theta_steer});
  moving_up_ = false;
  if (state_ == StackerState::kStanding) {
    stood_at_ = order_->stand;
  } else {
    finish_order({RobotEvent::Kind::kDone, order_->order_id, order_->drop_area_id, -1, {}});
  }
  fire(StackerEvent::kDocked);
}

void Stacker::handle_forks() {
  if (time_ < forks_done_at_) return;
  const Pose2& truth = body_.pose();
  const Vec2 on_forks =
      truth.position() + carried_offset(config_.docking, config_.body.geometry) * heading_of(truth.yaw);
  if (state_ == StackerState::kLifting) {
    int nearest = -1;
    double best = 0.4;  // the pallet's centre within this of the forks' middle, m
    for (const auto& [id, pose] : standing_) {
      const double d = geometry::distance(pose.position(), on_forks);
      if (d < best) {
        best = d;
        nearest = id;
      }
    }
    if (nearest < 0) {
      finish_order({RobotEvent::Kind::kFailed,
                    order_->order_id,
                    "docked at " + order_->pick_area_id + " but no pallet is on the forks",
                    -1,
                    {}});
      enter(StackerState::kToHome);
      return;
    }
    carried_ = nearest;
    reports_.add({RobotEvent::Kind::kLifted, order_->order_id, "", carried_, {}});
    fire(order_->drop_area_id.empty() ? StackerEvent::kHold : StackerEvent::kForksUp);
    return;
  }
  const RobotEvent done{
      RobotEvent::Kind::kDone, order_->order_id, order_->drop_area_id, carried_, {on_forks.x, on_forks.y, truth.yaw}};
  carried_ = -1;
  finish_order(done);
  fire(StackerEvent::kForksDown);
}

void Stacker::finish_order(RobotEvent event) {
  reports_.add(std::move(event));
  order_.reset();
}

}  // namespace fleet::robot
