#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "control/docking_law.hpp"
#include "control/docking_run.hpp"
#include "control/straight_back.hpp"
#include "control/tricycle_pursuit.hpp"
#include "map/site_map.hpp"
#include "perception/stacker_cameras.hpp"
#include "robot/navigation.hpp"
#include "robot/order_reporter.hpp"
#include "robot/robot.hpp"
#include "robot/stacker/stacker_job.hpp"
#include "robot/stacker/stacker_sweeps.hpp"
#include "sim/tricycle.hpp"
#include "task/task_executor.hpp"
#include "vehicle/profile.hpp"

namespace fleet::robot {

struct StackerConfig {
  sim::TricycleParams body;
  control::DockingParams docking;
  control::TricyclePursuitParams pursuit;
  /// Frames searched at 5 Hz on a site (10 in dock-eval): a 640 x 480 frame takes about 12 ms to
  /// render and search, and a soak runs several stackers at five times real time on two cores.
  perception::StackerDetectorParams detector{.rate_hz = 5.0};
  /// The pose sensor standing in for the thesis's GPS and compass [Stacker thesis, section 8.1],
  /// read at its rate and blended into the odometry on the roads. While docking the law steers
  /// by odometry alone, anchored where the sensor put the stacker when the docking began.
  control::PoseSensorNoise pose_noise{0.03, 0.0175};
  control::OdometryNoise odometry;
  double pose_rate_hz = 10.0;
  double pose_blend = 0.1;  ///< share of each sensor reading blended into the estimate
  double control_rate_hz = 20.0;
  control::StraightBackParams move_up;  ///< a loader's transporter backing up behind its picker
  double lift_time = 4.0;               ///< forks up or down, s (an SPE200's 0.1 m/s over a pallet's clearance)
  /// Bays, places and docking areas: a docking that failed at a drop place or a bay is tried
  /// again from target 1 this many times before the stacker stands and reports it.
  int max_dock_attempts = 3;
  // The safety stop and the look ahead along the path (other robots' published footprints).
  double safety_gap = 0.10;                            ///< metres
  double work_area_margin = 0.10;                      ///< metres round the bodies a docking sweeps
  double stale_after = 0.5;                            ///< sim seconds
  double neighbour_max_speed = 1.2;                    ///< m/s
  double safety_scan_range = 2.2;                      ///< metres: the S300's protective field at the plant's speeds
  double clearance_lookahead = 3.0;                    ///< metres of path swept for other robots
  double clearance_sample = 0.1;                       ///< metres between swept poses
  double clearance_margin = 0.15;                      ///< metres round the other robots
  planning::LidarConfiguration lidar{360, 8.0, 0.05};  ///< two S300s, 270 deg each, merged
  bool traffic = false;
  double siding_timeout = 30.0;
  std::shared_ptr<const map::RoadGraph> route_graph;
  double grid_resolution = 0.05;  ///< static grid of the legs off the roads, metres
  /// The pallets' pitch along a row: the docking area extends half of it each side, m.
  double row_pitch = 1.3;

  /// Settings for a fleet of this profile (footprint, speeds).
  static StackerConfig for_vehicle(const vehicle::VehicleProfile& profile);
};

/// One stacker [Stacker thesis]: its simulated tricycle body, depth cameras and pose sensor, and
/// its software. On the roads it follows its traffic-granted route by pure pursuit of the rear
/// axle; at a place it docks in reverse with the docking law and the camera-based pallet
/// detection, lifts, drives on, docks the carried pallet onto the drop place and lowers it; at
/// home it reverses into its bay the same way. What every robot type shares it holds in its
/// Navigation. The reported pose is the body's centre (the footprint's), the control reference the
/// rear-axle midpoint.
class Stacker : public Robot {
 public:
  Stacker(const StackerConfig& config, std::shared_ptr<const map::SiteMap> site, const geometry::Pose2& home,
          std::uint64_t seed, std::uint64_t stream);

  std::string refusal(orders::OrderKind kind) const override;
  bool submit(const task::TaskOrder& order, std::string* why) override;
  /// False, with the order left running, once the pallet is lifted.
  bool withdraw() override;
  void set_paused(bool paused) override { paused_ = paused; }
  bool set_obstacle(const std::string& id, bool enabled) override;
  void set_standing_loads(const std::map<int, geometry::Pose2>& standing) override { standing_ = standing; }
  void set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph) override;
  Navigation& navigation() override { return nav_; }
  const Navigation& navigation() const override { return nav_; }
  void set_traffic_grant(const TrafficPermit& permit) override;

  void step() override;
  double step_period() const override { return 1.0 / config_.control_rate_hz; }
  double time() const override { return time_; }

  RobotStatus status() const override;
  std::vector<RobotEvent> take_events() override { return reports_.take_events(); }
  TrafficRoute traffic_route() const override;
  DockingView docking_view() const override;

  // For tests and logs.
  StackerState state() const { return state_; }
  const geometry::Pose2& rear_axle() const { return body_.pose(); }
  const control::DockingLaw* docking_law() const { return law_ ? &*law_ : nullptr; }

 private:
  /// The body's centre, where the rear axle's estimate puts it.
  geometry::Pose2 estimate() const;
  std::optional<std::string> order_id() const;
  /// A transition of the job's table; false (and nothing changes) when the table has none.
  bool fire(StackerEvent event);
  void enter(StackerState state);
  /// The route to where the current state drives; false when there is none for now.
  bool plan_route();
  void drive();
  void dock();
  void handle_forks();
  void start_docking();
  /// A move order straight back along its line (StackerEvent::kMoveUp): no route, no turn.
  void start_moving_up();
  void move_up();
  /// Holding its load with no drop place yet: goes where the order now has it stand, or on to the
  /// drop place once the order names one.
  void hold();
  /// The docking law's settings for the docking, placing or parking the state leads to.
  control::DockingParams docking_params() const;
  /// way_out_ for the path just adopted.
  void note_way_out();
  double clearance_ahead() const;
  void update_sensors();
  void apply(const sim::TricycleCommand& command);
  /// Where the docking law starts from for the current state: the place (or bay) pose it docks to.
  geometry::Pose2 dock_prior() const;
  /// Where the route of the current state ends: a docking's approach, or the lane short of a stand.
  geometry::Pose2 route_goal() const;
  perception::PalletRow pallet_row(const geometry::Pose2& place, double base_height) const;
  void finish_order(RobotEvent event);
  void update_centre();

  StackerConfig config_;
  geometry::Pose2 home_;
  geometry::Footprint footprint_;
  StackerSweeps sweeps_{config_};
  Navigation nav_;
  sim::Tricycle body_;
  geometry::Pose2 estimate_;  ///< rear axle
  geometry::Pose2 truth_centre_;
  std::mt19937_64 rng_;
  double time_ = 0.0;
  double next_pose_reading_ = 0.0;
  double next_scan_ = 0.0;
  OrderReporter reports_;

  StackerState state_ = StackerState::kIdle;
  std::optional<task::TaskOrder> order_;
  bool need_route_ = false;
  double next_route_try_ = 0.0;
  std::optional<control::DockingLaw> law_;
  std::optional<control::StraightBack> back_;  ///< moving up straight back instead of docking
  bool moving_up_ = false;                     ///< the move order under way is a move up
  std::optional<geometry::Pose2> stood_at_;    ///< the order's stand it reached last, holding its load
  std::optional<perception::StackerCameraDetector> detector_;
  std::optional<geometry::Pose2> detected_pallet_;  ///< the cameras' latest find, until a frame finds nothing
  int dock_attempts_ = 0;
  std::optional<control::DockingPhase> shown_phase_;  ///< the docking phase the detail shows
  std::vector<geometry::Vec2> work_area_;             ///< while docking: what the manoeuvre sweeps
  std::vector<geometry::Vec2> keep_clear_;    ///< docked: both ways out onto the lane (TrafficRoute::keep_clear)
  bool area_clear_ = false;                   ///< traffic holds work_area_ for it (or traffic is off)
  std::vector<geometry::Vec2> way_out_;       ///< what the way out of a dock or bay onto its route sweeps
  std::vector<geometry::Vec2> arrival_area_;  ///< what the docking at the end of its route sweeps
  double forks_done_at_ = 0.0;
  int carried_ = -1;
  bool paused_ = false;
  bool held_by_traffic_ = false;
  bool blocked_ = false;
  bool at_siding_end_ = false;  ///< the pursuit reached the end of the siding it was sent to
  geometry::Vec2 planned_end_;  ///< where its own plan's route ends: the docking's start
  std::map<int, geometry::Pose2> standing_;
  control::BodyTwist twist_;
};

}  // namespace fleet::robot
