#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "map/site_map.hpp"
#include "perception/marker_camera.hpp"
#include "perception/pallet_world.hpp"
#include "planning/dynamic_grid.hpp"
#include "planning/octomap_layer.hpp"
#include "robot/forklift/simulated_forklift.hpp"
#include "robot/item_handler.hpp"
#include "robot/navigation.hpp"
#include "robot/order_reporter.hpp"
#include "robot/robot.hpp"
#include "task/task_executor.hpp"
#include "vehicle/profile.hpp"

namespace fleet::robot {

struct ForkliftConfig {
  /// The robot type this software drives, for messages ("forklift", "picker").
  std::string type_name = "forklift";
  /// False for a base without forks (the picker, the cart): it takes no transport.
  bool forks = true;
  SimulatedForkliftParams sim;
  task::ExecutorParams task;  ///< its follower defaults to the regulated one
  perception::MarkerCameraParams camera;
  double control_rate_hz = 70.0;  ///< pose and control rate [Forklift thesis, Table 3.1]
  double grid_resolution = 0.02;  ///< static grid of the route planner, metres
  /// Another robot closer than this ahead (footprint to footprint) stops this one.
  /// The safety stop keeps at least this gap to every other robot, whatever the task state.
  double safety_gap = 0.03;     ///< metres
  double stop_distance = 0.08;  ///< metres: pose latency and the sweep of a turn need a margin
  /// Under the coordination core (`traffic.core: places`), the clearance ahead at which another
  /// robot's body stops this one, in place of stop_distance: the core grants only places whose
  /// bodies keep `traffic.places_margin` apart, and a robot that stopped short of its place for a body
  /// the core keeps clear of it would never arrive. Negative: stop_distance, m.
  double planned_stop_distance = -1.0;
  /// Under the coordination core a route handed by traffic leaves a lasting safety stop standing
  /// (the robot has not moved away from the body it stopped for): the core plans a robot that
  /// reports one to stay (TrafficRoute::stopped_for), and a robot handed routes every few seconds
  /// would otherwise never report it.
  bool stop_outlasts_reroute = false;
  double neighbour_margin = 0.03;  ///< metres added around other robots' footprints
  /// A neighbour's pose older than this counts as everywhere it could have reached since
  /// (the stale-neighbour rule).
  double stale_after = 0.5;          ///< sim seconds
  double neighbour_max_speed = 0.3;  ///< m/s, bounds how far a stale neighbour may have moved
  /// Other robots are this tall; the UWB tag sits at the sim's tag height. A robot shadows an
  /// anchor only where the anchor-tag ray is still below its top (see uwb_blockers()).
  double robot_height = 0.15;  ///< metres
  /// A UWB range whose line from the anchor passes this close to an enabled static obstacle of
  /// the map (grown by the estimate's uncertainty) is left out of the fix: a shadowed range is
  /// always too long, and at rest the filter would average the bias into a 10 cm error.
  /// Negative: every range is used (the thesis's behaviour).
  double anchor_shadow_margin = 0.05;  ///< metres
  /// Traffic control: report the road part of every route and drive only as far as
  /// the server grants (set_traffic_grant). Off: the thesis's local avoidance alone.
  bool traffic = false;
  /// Sim seconds a robot stands held on a siding before it plans its own way on and asks for it.
  /// The manager calls it back sooner (its yield_timeout, 20 s); a restarted manager does not
  /// know the robot waits on a siding: it sees a route that has arrived.
  double siding_timeout = 30.0;
  /// The graph routes are planned on; the traffic manager's one-way graph when traffic is on.
  /// Null: the site's road graph.
  std::shared_ptr<const map::RoadGraph> route_graph;

  /// The pallets' lift tolerances (simulation truth); carry_x and marker_offset come from
  /// task.geometry, so forks and pallets agree.
  perception::PalletWorldParams pallet_world;
  planning::LidarConfiguration lidar;
  // Distances of the local planner and the safety stop; they follow the vehicle's size
  // (for_vehicle).
  double clearance_lookahead = 1.0;  ///< metres of path checked [Forklift thesis, section 5.3]
  double clearance_sample = 0.03;    ///< metres between the footprint poses swept along the path
  double clearance_margin = 0.01;    ///< metres around our footprint in that sweep
  double temporary_size = 0.3;       ///< side of a temporary obstacle box, metres
  /// Lidar returns within this range feed the safety stop: the footprint's reach plus what the
  /// stop's 0.4 s horizon can cover at top speed, with room to spare.
  double safety_scan_range = 0.6;  ///< metres
  double escape_within = 0.10;     ///< metres: a refused robot this close to a body steps away
  double escape_speed = 0.03;      ///< m/s of that step
  /// A safety stop is the same stop while the robot stays within this of where it began.
  double stop_moved = 0.05;          ///< metres
  double neighbour_max_reach = 3.0;  ///< metres: caps a stale neighbour's disc
  /// Metres round a neighbour's reported body within which what the lidar saw is that neighbour
  /// (planning::DynamicGridConfiguration::reported_tolerance).
  double reported_tolerance = 0.06;
  double uwb_shadow_reach = 0.15;   ///< metres from the tag within which a robot shadows anchors
  double siding_end_margin = 0.03;  ///< metres short of a siding's end the robot stops

  static ForkliftConfig defaults();
  /// The defaults made for a vehicle of this profile: every length follows the footprint's length
  /// (or width, for the wheel track), every manoeuvre speed the profile's top speed, the
  /// accelerations its acceleration, the obstacle slow-down its braking distance. For the forklift
  /// type's own profile (the thesis's 25 x 16 cm robot, vehicle::find_robot_type("forklift"))
  /// every factor is exactly 1 and this is defaults(). The follower's v_max and omega_max stay the
  /// software's setting (the agent sets them).
  static ForkliftConfig for_vehicle(const vehicle::VehicleProfile& profile);
};

/// One forklift: its simulated body and sensors (SimulatedForklift), the marker camera on the
/// pallets it knows of, and its software: EKF pose into the task executor [Forklift thesis, Fig. 6.9],
/// route planning on the road graph with the static grid [Forklift thesis, chapter 5], pallet search,
/// pick and place [Forklift thesis, sections 6.2-6.3]. What every robot type shares it holds in
/// its Navigation; a type that handles items at stops (the picker's arm) plugs in an ItemHandler.
class Forklift : public Robot {
 public:
  Forklift(const ForkliftConfig& config, std::shared_ptr<const map::SiteMap> site, const geometry::Pose2& home,
           std::uint64_t seed, std::uint64_t stream, std::unique_ptr<ItemHandler> items = nullptr);

  // --- inputs ---------------------------------------------------------------------------------
  /// A forklift performs transports and moves; no pickItem.
  std::string refusal(orders::OrderKind kind) const override;
  bool submit(const task::TaskOrder& order, std::string* why) override;
  /// False, with the order left running, once the pallet is on the forks: it cannot be cancelled
  /// then [Forklift thesis, section 6.4], and a robot that stopped with it would stand in the lane for good.
  bool withdraw() override;
  bool set_drop(const std::string& area_id, const geometry::Pose2& area) override {
    return executor_.set_drop(area_id, area);
  }
  void set_paused(bool paused) override;
  bool set_obstacle(const std::string& id, bool enabled) override;
  /// The standing pallets. Pallets carried by other robots are left out; the one on these forks
  /// is left alone.
  void set_standing_loads(const std::map<int, geometry::Pose2>& standing) override;
  void set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph) override;
  Navigation& navigation() override { return nav_; }
  const Navigation& navigation() const override { return nav_; }
  void set_traffic_grant(const TrafficPermit& permit) override;

  /// One control step of 1 / control_rate_hz sim seconds.
  void step() override;
  double step_period() const override { return 1.0 / config_.control_rate_hz; }
  double time() const override { return sim_.time(); }

  // --- outputs --------------------------------------------------------------------------------
  RobotStatus status() const override;
  std::vector<RobotEvent> take_events() override { return reports_.take_events(); }
  TrafficRoute traffic_route() const override;

 private:
  std::optional<std::string> order_id() const;
  const geometry::Footprint& footprint() const { return config_.sim.forklift.footprint; }
  /// The dynamic grid from the neighbours and a lidar scan, and temporaries seen free removed.
  void update_surroundings();
  /// Stops for what is in the way (met by the path sweep at `blocked_at`) and holds at the end
  /// of the grant; returns the traffic room.
  double follow_traffic(double t, double clearance, const geometry::Pose2& blocked_at);
  /// The clearance ahead at which another body stops the robot.
  double stop_distance() const {
    return config_.planned_stop_distance >= 0.0 ? config_.planned_stop_distance : config_.stop_distance;
  }
  void answer_plan_requests();
  void collect_reports();
  /// How far the robot drives along its path before its swept footprint meets another robot's
  /// cells or a lidar return; `blocked_at` is the swept pose that met them.
  double clearance_ahead(geometry::Pose2& blocked_at) const;
  /// What the body sweeps beyond the road's last point of its path, turning off the lane into
  /// its goal beside the road and on into the loading area at `place` (a pick or a drop), as
  /// TrafficRoute::arrival_area; empty when the goal is on the road.
  std::vector<geometry::Vec2> arrival_sweep(std::optional<geometry::Vec2> place) const;
  /// The loading area a path planned for `purpose` leads to, when it leads to one.
  std::optional<geometry::Vec2> place_of(task::PlanPurpose purpose) const;
  std::vector<geometry::Polygon> uwb_blockers() const;
  /// Anchors the map shows behind an enabled static obstacle, seen from the estimate.
  std::vector<std::size_t> shadowed_anchors() const;

  ForkliftConfig config_;
  Navigation nav_;
  SimulatedForklift sim_;
  perception::MarkerCamera camera_;
  perception::PalletWorld pallets_;
  task::TaskExecutor executor_;
  // Local planning [Forklift thesis, section 5.3]: the other robots on a dynamic grid, temporary
  // obstacles for the ones in the way, removed once their area is seen free.
  planning::DynamicGrid dynamic_;
  // The onboard lidar's scans (beyond the thesis, whose conclusion asks for range sensing
  // [Forklift thesis]) into OctoMap, projected onto the dynamic grid as its sensed layer.
  planning::OctoMapLayer octomap_;
  std::vector<geometry::Vec2> arrival_area_;  ///< arrival_sweep() of the path adopted last
  OrderReporter reports_;
  control::BodyTwist command_;
  int carried_pallet_ = -1;
  std::optional<std::pair<int, geometry::Pose2>> last_put_down_;
  bool blocked_by_neighbour_ = false;
  double next_dynamic_update_ = 0.0;
  double blocked_since_ = -1.0;
  std::map<std::string, int> seen_free_;
  int next_temporary_ = 1;
  bool held_by_traffic_ = false;
  std::unique_ptr<ItemHandler> items_;  ///< the tool at item stops; null: no pick orders
};

}  // namespace fleet::robot
