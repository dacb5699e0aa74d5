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
#include "planning/grid_astar.hpp"
#include "planning/lidar_sim.hpp"
#include "planning/octomap_layer.hpp"
#include "planning/road_planner.hpp"
#include "planning/route_planner.hpp"
#include "planning/static_grid.hpp"
#include "robot/simulated_forklift.hpp"
#include "task/task_executor.hpp"
#include "vehicle/profile.hpp"

namespace fleet::robot {

struct ForkliftConfig {
  SimulatedForkliftParams sim;
  task::ExecutorParams task;  ///< its follower defaults to the regulated one
  perception::MarkerCameraParams camera;
  double control_rate_hz = 70.0;  ///< pose and control rate [Forklift thesis, Table 3.1]
  double grid_resolution = 0.02;  ///< static grid of the route planner, metres
  /// Another robot closer than this ahead (footprint to footprint) stops this one.
  /// The safety stop keeps at least this gap to every other robot, whatever the task state.
  double safety_gap = 0.03;        ///< metres
  double stop_distance = 0.08;     ///< metres: pose latency and the sweep of a turn need a margin
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
  double uwb_shadow_reach = 0.15;    ///< metres from the tag within which a robot shadows anchors
  double siding_end_margin = 0.03;   ///< metres short of a siding's end the robot stops

  static ForkliftConfig defaults();
  /// The defaults made for a vehicle of this profile: every length follows the footprint's length
  /// (or width, for the wheel track), every manoeuvre speed the profile's top speed, the
  /// accelerations its acceleration, the obstacle slow-down its braking distance. For the forklift
  /// type's own profile (the thesis's 25 x 16 cm robot, vehicle::find_robot_type("forklift"))
  /// every factor is exactly 1 and this is defaults(). The follower's v_max and omega_max stay the
  /// software's setting (the agent sets them).
  static ForkliftConfig for_vehicle(const vehicle::VehicleProfile& profile);
};

/// Another robot as this one knows it (from FleetView).
struct Neighbour {
  std::string robot_id;
  geometry::Pose2 pose;
  geometry::Footprint footprint;
  double speed = 0.0;
  double age = 0.0;  ///< sim seconds since the pose was measured
};

/// The road part of the route being driven, for the traffic manager (see model::TrafficRequest).
struct TrafficRoute {
  std::uint64_t version = 0;
  std::vector<int> points;  ///< graph point ids; empty while off the roads
  double progress = 0.0;    ///< metres driven from the first point
  /// The robot whose body the safety check has kept this one standing for, once the stop has
  /// lasted 3 s sim on this route (forklift.cpp, kReportStopAfter): the traffic manager then sees
  /// who waits for whom even where the grants alone show no cycle.
  std::vector<std::string> stopped_for;
};

/// The version of the first route of an agent started at wall time `now`. Versions must grow
/// across restarts of the agent too, or the traffic manager, which still knows the robot, would
/// take a restarted agent's routes for stale ones: sixteen per second of wall time since
/// 2023-11-14 (unix time 1.7e9). An agent takes two per new route, so a restarted one starts
/// above its previous run unless that run planned eight routes a second or more on average.
/// 64 bits: in 32, sixteen a second would run out on 2032-05-17.
std::uint64_t first_route_version(std::chrono::system_clock::time_point now);
/// The version of the agent's next own route after `current`: the next even number. The
/// manager's re-routes take odd ones (its version + 1), so the two never give one version to
/// different routes.
std::uint64_t next_own_route_version(std::uint64_t current);

/// A grant from the traffic manager (see traffic::Grant and model::TrafficGrant).
struct TrafficPermit {
  std::uint64_t version = 0;
  int granted_index = 0;
  double granted_distance = 0.0;
  std::vector<std::string> blocked_by;
  /// Non-empty: drive this route (of `version`) instead; `siding` when it leads to a siding to
  /// wait on rather than towards the goal.
  std::vector<int> route;
  bool siding = false;
};

/// What happened during a step, for the agent to report.
struct ForkliftEvent {
  enum class Kind {
    kPhase,      ///< the order's phase changed: `text` is TO_PICK, SEARCHING, PICKING, TO_DROP, DROPPING
    kLifted,     ///< a pallet is on the forks: `pallet_id`
    kDone,       ///< pallet put down on the drop area: `pallet_id`, `pallet_pose` (truth)
    kAreaEmpty,  ///< no pallet at the pick area: the order fails, the robot goes home
    kFailed,     ///< the order failed: `text` says why
    kHome,       ///< home reached, idle
    kState,      ///< the task state changed: `text` is its name
  };
  Kind kind = Kind::kState;
  std::string order_id;
  std::string text;
  int pallet_id = -1;
  geometry::Pose2 pallet_pose;
};

/// One forklift: its simulated body and sensors (SimulatedForklift), the marker camera on the
/// pallets it knows of, and its software: EKF pose into the task executor [Forklift thesis, Fig. 6.9],
/// route planning on the road graph with the static grid [Forklift thesis, chapter 5], pallet search,
/// pick and place [Forklift thesis, sections 6.2-6.3]. No I/O: the agent feeds it what arrives over DDS
/// and publishes what it reports.
class Forklift {
 public:
  Forklift(const ForkliftConfig& config, std::shared_ptr<const map::SiteMap> site, const geometry::Pose2& home,
           std::uint64_t seed, std::uint64_t stream);

  // --- inputs ---------------------------------------------------------------------------------
  /// An order; false with the reason when the robot cannot take it now.
  bool submit(const task::TaskOrder& order, std::string* why);
  /// The server took the order away: drop it and go home. False, with the order left running,
  /// once the pallet is on the forks: it cannot be cancelled then [Forklift thesis, section 6.4], and a robot
  /// that stopped with it would stand in the lane for good.
  bool withdraw();
  void set_paused(bool paused);
  /// A designated static obstacle switched on or off. True when the robot is driving and asked
  /// for a new plan on the changed grid.
  bool set_obstacle(const std::string& id, bool enabled);
  /// Where the pallets really stand (simulation truth, owned by the server). Pallets carried by
  /// other robots are left out; the one on these forks is left alone.
  void set_standing_pallets(const std::map<int, geometry::Pose2>& standing);
  void set_neighbours(std::vector<Neighbour> neighbours);
  /// Simulation truth of the other robots' footprints: what the onboard lidar sees.
  void set_true_neighbours(std::vector<geometry::Polygon> footprints);
  /// The server switched this robot to another map of the same site (a revision: same areas,
  /// homes and anchors; see map::revision_mismatch): roads, obstacles and planners come from
  /// it now, and the task replans on it. `route_graph` replaces config.route_graph.
  void set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph);
  const map::SiteMap& site() const { return *site_; }
  /// The traffic manager's latest grant for this robot (traffic on only).
  void set_traffic_grant(const TrafficPermit& permit);

  /// One control step of 1 / control_rate_hz sim seconds.
  void step();
  double step_period() const { return 1.0 / config_.control_rate_hz; }

  // --- outputs --------------------------------------------------------------------------------
  std::vector<ForkliftEvent> take_events();
  double time() const { return sim_.time(); }
  const geometry::Pose2& truth() const { return sim_.truth(); }
  geometry::Pose2 estimate() const { return sim_.estimate(); }
  std::array<double, 9> covariance() const { return sim_.covariance(); }
  double localization_score() const { return sim_.localization_score(); }
  const control::BodyTwist& command() const { return command_; }
  std::string task_state() const;
  /// Why the robot waits or failed, empty otherwise.
  const std::string& detail() const { return detail_; }
  std::optional<std::string> order_id() const;
  int carried_pallet() const { return carried_pallet_; }
  /// The path being followed (for RobotPath and the web view).
  const std::vector<geometry::Vec2>& path() const { return path_; }
  const geometry::Footprint& footprint() const { return config_.sim.forklift.footprint; }
  /// The route to report to the traffic manager, with the progress along it.
  TrafficRoute traffic_route() const;
  /// Its version alone: changes with every new route (no copy of the route).
  std::uint64_t route_version() const { return route_version_; }
  /// Whether the robot stands at the end of what traffic granted it.
  bool held_by_traffic() const { return held_by_traffic_; }

 private:
  /// The site's designated obstacles as the site file sets them at the start.
  void reset_obstacles();
  void answer_plan_requests();
  void adopt_path(const planning::Route& route);
  void adopt_traffic_route(const TrafficPermit& permit);
  double path_position() const;
  double traffic_room();
  void collect_reports();
  double clearance_ahead() const;
  control::BodyTwist safe(const control::BodyTwist& cmd) const;
  /// Whether `cmd` would bring the footprint within `safety_gap` of another robot (see safe()).
  bool moves_too_close(const control::BodyTwist& cmd) const;
  std::vector<geometry::Polygon> uwb_blockers() const;
  /// Anchors the map shows behind an enabled static obstacle, seen from the estimate.
  std::vector<std::size_t> shadowed_anchors() const;

  ForkliftConfig config_;
  std::shared_ptr<const map::SiteMap> site_;
  SimulatedForklift sim_;
  perception::MarkerCamera camera_;
  perception::PalletWorld pallets_;
  task::TaskExecutor executor_;
  planning::StaticGrid static_grid_;
  // Local planning [Forklift thesis, section 5.3]: the other robots on a dynamic grid, temporary
  // obstacles for the ones in the way, removed once their area is seen free.
  planning::DynamicGrid dynamic_;
  // The onboard lidar (beyond the thesis, whose conclusion asks for range sensing [Forklift thesis]) into OctoMap,
  // projected onto the dynamic grid as its sensed layer.
  planning::LidarSim lidar_;
  planning::OctoMapLayer octomap_;
  std::vector<geometry::Polygon> true_neighbours_;
  /// The lidar's latest returns near the robot, placed with the pose estimate of the scan: the
  /// safety stop reads them relative to the estimate now, so a bias of the estimate cancels.
  std::vector<geometry::Vec2> near_returns_;
  planning::RoadPlanner road_;
  planning::GridAStar grid_astar_;
  planning::RoutePlanner routes_;
  // Under traffic control routes_ plans on the one-way graph; when a static obstacle closes every
  // way along it, the robot plans on the site's graph in both directions (the traffic manager
  // keeps opposite directions apart in a corridor).
  planning::RoadPlanner two_way_road_;
  planning::RoutePlanner two_way_routes_;
  std::uint64_t grid_revision_ = 0;
  std::vector<Neighbour> neighbours_;
  std::map<std::string, bool> obstacles_;
  std::vector<ForkliftEvent> events_;
  std::vector<geometry::Vec2> path_;
  control::BodyTwist command_;
  int carried_pallet_ = -1;
  std::optional<std::pair<int, geometry::Pose2>> last_put_down_;
  std::string detail_;
  bool blocked_by_neighbour_ = false;
  double next_dynamic_update_ = 0.0;
  double blocked_since_ = -1.0;
  /// A safety stop for one robot's body, kept through the flicker of a stop (the check clears for
  /// a step as poses arrive, then stops again): who, since when, where this robot stood, when last.
  struct SafetyStop {
    std::string robot_id;
    double since = 0.0;
    geometry::Vec2 where;
    double last_seen = -1.0;
    /// Still the same stop at time `t` with this robot at `here`: seen lately, not moved more
    /// than `moved` away.
    bool current(double t, geometry::Vec2 here, double moved) const;
  };
  SafetyStop safety_stop_;
  void note_safety_stop(double t, const std::string& nearest);
  std::map<std::string, int> seen_free_;
  int next_temporary_ = 1;

  // Traffic control. The path's arc length is the common measure: the road part of the path
  // starts at `road_start_` and its graph points sit at `road_start_ + road_cum_[i]`.
  std::vector<double> path_cum_;  ///< metres from the path's start to each point
  mutable double path_s_ = 0.0;   ///< where the robot was last found along the path
  std::uint64_t route_version_ = 0;
  std::vector<int> road_points_;
  std::vector<double> road_cum_;
  double road_start_ = 0.0;
  bool in_siding_ = false;
  double siding_held_since_ = -1.0;  ///< sim time it was first held on its siding, -1 when not
  TrafficPermit permit_;
  std::optional<TrafficPermit> pending_route_;  ///< an instruction to adopt at the next plan
  /// The last road point of this robot's own plan and the path after it (off the road to the
  /// loading area or home): kept through the manager's re-routes and sidings, so a route that
  /// comes back to that point still ends where the task needs the robot.
  int goal_point_ = -1;
  std::vector<geometry::Vec2> goal_leg_;
  bool held_by_traffic_ = false;
};

}  // namespace fleet::robot
