#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "control/pallet_pick.hpp"
#include "control/pallet_place.hpp"
#include "control/pallet_search.hpp"
#include "control/path_follower.hpp"
#include "perception/marker_camera.hpp"
#include "task/task_state_machine.hpp"

namespace fleet::task {

/// One line of a pick order as the robot drives it: the place (its loading-area pose), the item
/// and how many boxes the arm takes there.
struct ItemStop {
  std::string place_id;
  geometry::Pose2 place;
  std::string item;
  int quantity = 0;
};

/// An order as the forklift sees it. A transport: where to pick, where to drop (loading-area
/// poses, yaw pointing from the pallet towards the approach road). A move: the parking place in
/// drop_area_id / drop_area (the pose the robot parks at). A pick: the stops in `items`, one per
/// line in the order they are driven, then the drop place in drop_area_id / drop_area.
struct TaskOrder {
  std::string order_id;
  std::string pick_area_id;
  geometry::Pose2 pick_area;
  std::string drop_area_id;
  geometry::Pose2 drop_area;
  orders::OrderKind kind = orders::OrderKind::kTransport;
  std::vector<ItemStop> items{};
  /// A pick order worked as a loader (docs/loader.md): each stop's boxes go on the
  /// pallet of a transporter standing behind the robot, and the order ends at the last stop.
  bool loader = false;
  /// A loader drives to and works only the stops before this one: it waits for an update of the
  /// order that releases the next (its transporter stands behind that stop). It waits where it
  /// stands while the pallet it loaded last moves up; for a new pallet, or none, it waits at home,
  /// out of the aisle the new transporter drives into.
  std::size_t released = std::numeric_limits<std::size_t>::max();
  /// A loader may drive to the stops before this one though they are not released yet: its
  /// transporter moves up ahead of it to stand behind the next. It waits at the stop, its arm still,
  /// until the stop is released.
  std::size_t approach = 0;
  /// Which transporter's pallet stands behind it: a new one holds no box yet.
  int pallet = 0;
  /// A transport with no drop place yet (a stacker's): where to stand with the load meanwhile, the
  /// body's centre (a loader's transporter behind its picker). An update of the same order moves
  /// it, or names the drop place.
  std::optional<geometry::Pose2> stand{};
};

enum class PlanPurpose { kToPick, kToDrop, kHome, kToPlace };
const char* to_string(PlanPurpose p);

/// A request for the planner. Answer with TaskExecutor::path_received or plan_failed quoting `id`;
/// answers to superseded requests are ignored.
struct PlanRequest {
  std::uint64_t id = 0;
  PlanPurpose purpose = PlanPurpose::kHome;
  geometry::Pose2 goal;
};

/// Something the agent publishes (OrderState, pallet inventory).
struct TaskReport {
  enum class Kind { kAccepted, kPicked, kAreaEmpty, kDropped, kCancelled, kFailed, kHomeReached, kArrived };
  Kind kind = Kind::kAccepted;
  std::string order_id;
  std::string area_id;  ///< the area concerned (picked from, empty, dropped on)
  std::string detail;   ///< failure reason
};
const char* to_string(TaskReport::Kind k);

struct ExecutorParams {
  control::FollowerParams follower;
  control::SearchParams search;
  control::PickParams pick;
  control::PlaceParams place;
  control::ForkliftGeometry geometry;
  int max_pick_attempts = 3;     ///< failed picks (search + pick again) before ERROR
  double replan_interval = 1.0;  ///< while WAITING for want of a plan, ask again this often, s
  /// A path whose end is further than this from the goal (the search pose, or home) is not an
  /// arrival: the executor plans again from where the robot stands, metres.
  double arrival_tolerance = 0.10;
  /// A pick order's stops: the robot's centre stands this far out from a place's pose (towards
  /// the road, along its yaw), side-on with the place on its left, within its arm's reach.
  double item_standoff = 1.0;  ///< metres
};

/// Per-step inputs, at the pose rate (70 Hz [Forklift thesis, Table 3.1]).
struct TaskInput {
  double time = 0.0;                                        ///< sim time, s
  geometry::Pose2 pose;                                     ///< localization estimate
  std::span<const perception::MarkerDetection> detections;  ///< frames since the last step
  double obstacle_distance = std::numeric_limits<double>::infinity();
  /// Metres along its path the robot may drive (control::FollowerInput::granted_distance).
  double granted_distance = std::numeric_limits<double>::infinity();
};

struct TaskOutput {
  control::BodyTwist twist;
  bool fork_up = false;
};

/// Runs an order on the forklift: the TaskStateMachine's table decides the state, this class
/// carries out each transition's Effect with the controllers of core/control.
///
/// How the agent drives it, every pose update (about 70 Hz):
///  1. Forward inputs as they arrive: submit() for an Order (the return value and `why` answer
///     it), path_received() / plan_failed() for planner answers, set_blocked() for traffic,
///     pause() / resume() / cancel() / fault() / reset() for operator commands.
///  2. Call step() with the pose estimate, the marker detections since the last call and the
///     clearance ahead; apply the returned twist and fork command to the body.
///  3. Drain take_plan_request() (at most one pending; a newer one supersedes) and hand it to
///     the planner; drain take_reports() into OrderState / pallet inventory and
///     take_transitions() into RobotState / OrderState; publish state(), phase() and
///     error_reason() in RobotState.
/// Nothing here blocks, sleeps or reads a clock: time comes in TaskInput::time.
class TaskExecutor {
 public:
  TaskExecutor(ExecutorParams params, geometry::Pose2 home);

  /// Accepts the order in IDLE or GO_HOME; otherwise returns false and says why. A transport
  /// order picks and drops; a move order drives to its place, which becomes the robot's home. A
  /// transport without a drop place (drop_area_id empty) stands with its load after the pick
  /// until set_drop() names one. The loader order under way is updated by one of the same id:
  /// the stops released and the pallet behind it.
  bool submit(const TaskOrder& order, std::string* why = nullptr);
  /// The drop place of a transport submitted without one; false when there is no such transport.
  bool set_drop(const std::string& area_id, const geometry::Pose2& area);
  void path_received(std::uint64_t request_id, std::vector<geometry::Pose2> path);
  void plan_failed(std::uint64_t request_id);
  void set_blocked(bool blocked);
  /// The map changed (an obstacle appeared or went): ask for a new plan to the current goal when
  /// driving or waiting for one. The robot stands until the answer comes.
  void replan();
  bool pause();
  bool resume();
  bool cancel(std::string* why = nullptr);
  void fault(const std::string& reason);
  /// The arm finished what PICK_ITEMS or DROP_ITEMS asked of it (the current line's boxes, or
  /// every box of the tour), or could not (`reason`). Ignored in any other state.
  void items_done(bool ok, const std::string& reason = {});
  /// A loader standing or going home until its next stop is released (TaskOrder::released).
  bool waits_for_release() const { return waiting_for_release_; }
  /// The line PICK_ITEMS works on (index into the order's items).
  std::size_t item_line() const { return item_line_; }
  /// Where the robot stands to pick or drop items at `place`: side-on, the place on its left.
  geometry::Pose2 item_pose(const geometry::Pose2& place) const;
  bool reset();
  void set_home(const geometry::Pose2& home) { home_ = home; }

  TaskOutput step(const TaskInput& input);

  std::optional<PlanRequest> take_plan_request();
  std::vector<TaskReport> take_reports();

  State state() const { return machine_.state(); }
  orders::OrderPhase phase() const { return machine_.phase(); }
  const std::string& error_reason() const { return machine_.error_reason(); }
  const std::optional<TaskOrder>& order() const { return order_; }
  bool carrying() const { return fork_up_; }
  const TaskStateMachine& machine() const { return machine_; }
  const control::PathFollower& follower() const { return follower_; }
  /// Transitions taken since the last call, oldest first: each one is published (RobotState,
  /// OrderState). Drained so that a long-running agent holds no growing log.
  std::vector<Transition> take_transitions();

 private:
  Transition fire(Event e, const std::string& reason = {});
  void apply(const Transition& tr);
  void request_plan(PlanPurpose purpose);
  /// A loader's next stop is not released: wait for it where it stands or at home.
  void hold_for_release();
  /// While waiting for a release: drive to the stop once released, or home once the pallet it
  /// waited behind has left.
  void follow_release();
  /// The pallet the loader set its last boxes on is the one to come behind the next stop: it
  /// moves up, and the loader waits where it stands.
  bool waits_in_place() const;
  /// A loader may drive to its next stop: it is released, or open to approach (TaskOrder::approach).
  bool stop_open() const;
  /// Waiting for a release where it stands: no path to follow, nothing to plan.
  bool stands_for_release() const { return waiting_for_release_ && !release_wait_home_; }
  geometry::Pose2 goal_for(PlanPurpose purpose) const;
  void report(TaskReport::Kind kind, const std::string& area, const std::string& detail = {});
  /// Reports how the order ended, forgets it and asks for the way home.
  void end_order(TaskReport::Kind kind, const std::string& area, const std::string& detail = {});

  ExecutorParams params_;
  geometry::Pose2 home_;
  TaskStateMachine machine_;
  control::PathFollower follower_;
  control::PalletSearch search_;
  control::PalletPick pick_;
  control::PalletPlace place_;
  std::optional<TaskOrder> order_;
  std::optional<PlanRequest> pending_request_;
  std::uint64_t next_request_id_ = 1;
  std::uint64_t active_request_id_ = 0;
  PlanPurpose active_purpose_ = PlanPurpose::kHome;
  bool have_path_ = false;
  bool blocked_ = false;
  bool waiting_for_plan_ = false;
  /// A loader whose next stop is not released yet (TaskOrder::released): it stands, or drives
  /// home to wait there (release_wait_home_).
  bool waiting_for_release_ = false;
  bool release_wait_home_ = false;
  /// The pallet the loader set its last boxes on (TaskOrder::pallet), 0 before the first.
  int loaded_pallet_ = 0;
  double last_request_time_ = 0.0;
  double now_ = 0.0;
  double last_time_ = std::numeric_limits<double>::quiet_NaN();
  bool fork_up_ = false;
  int pick_attempts_ = 0;
  std::size_t item_line_ = 0;
  std::vector<TaskReport> reports_;
  std::vector<Transition> transitions_;
};

}  // namespace fleet::task
