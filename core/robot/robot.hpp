#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "control/twist.hpp"
#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "map/site_map.hpp"
#include "orders/order_kind.hpp"
#include "task/task_executor.hpp"

namespace fleet::robot {

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
  /// lasted 3 s sim on this route (safety_stop.cpp, kReportStopAfter): the traffic manager then
  /// sees who waits for whom even where the grants alone show no cycle.
  std::vector<std::string> stopped_for;
  /// Off the roads: the area the manoeuvre about to start or under way sweeps (model::TrafficRequest).
  geometry::Polygon work_area;
  /// On the road: what the robot sweeps turning off the route's end into its goal beside the road
  /// (model::TrafficRequest::arrival_area).
  geometry::Polygon arrival_area;
  /// Off the road, docked: the area its way out will sweep (model::TrafficRequest::keep_clear).
  geometry::Polygon keep_clear;
};

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
  /// The answer to a work area (TrafficRoute::work_area) rather than a grant along a route.
  enum class Area { kNone, kClear, kWaiting };
  Area area = Area::kNone;
};

/// A docking as the robot knows it, for the web view; map frame, the frame of estimate().
struct DockingView {
  /// Where the rear axle is steered to before the final approach: target 1, then target 2.
  std::vector<geometry::Vec2> targets;
  /// The pallet the cameras detect now: its centre and entry-axis yaw.
  std::optional<geometry::Pose2> detected_pallet;

  bool empty() const { return targets.empty() && !detected_pallet; }
};

/// What happened during a step, for the agent to report. The same for every robot type: the
/// load is whatever the type carries (a pallet for a forklift).
struct RobotEvent {
  enum class Kind {
    kPhase,      ///< the order's phase changed: `text` is TO_PICK, SEARCHING, PICKING, TO_DROP, DROPPING
    kLifted,     ///< a load was taken up: `load_id`
    kDone,       ///< the order's goal reached; a load put down there: `load_id`, `load_pose` (truth)
    kAreaEmpty,  ///< no load at the pick place: the order fails, the robot goes home
    kFailed,     ///< the order failed: `text` says why
    kHome,       ///< home reached, idle
    kState,      ///< the task state changed: `text` is its name
  };
  Kind kind = Kind::kState;
  std::string order_id;
  std::string text;
  int load_id = -1;
  geometry::Pose2 load_pose;
};

/// What a robot tells of itself at a moment, the same for every type (model::RobotState and
/// model::RobotTruth are made of it).
struct RobotStatus {
  double time = 0.0;                   ///< sim seconds since the robot started
  geometry::Pose2 truth;               ///< where the body really is (simulation truth): its footprint's centre
  geometry::Pose2 estimate;            ///< where the robot believes it is, the same point
  std::array<double, 9> covariance{};  ///< of the estimate, row-major over x, y, yaw
  double localization_score = 1.0;
  control::BodyTwist command;  ///< the twist commanded in the last step
  std::string task_state;
  std::string detail;  ///< why the robot waits or failed, empty otherwise
  std::optional<std::string> order_id;
  int carried_load = -1;  ///< the id of the load it carries, -1 when none
  geometry::Footprint footprint;
  bool held_by_traffic = false;  ///< it stands at the end of what traffic granted it
  /// A picker on a loader walk (ItemHandler::LoaderProgress): the stop it stands at, -1 while it
  /// drives; the boxes set on transporters' pallets in the order so far.
  int walk_stop = -1;
  int boxes_loaded = 0;
};

class Navigation;  // robot/navigation.hpp

/// One robot of any type, as the agent drives it: its simulated body and sensors and its own
/// software. No I/O: the agent feeds it what arrives over DDS and publishes what it reports.
/// What every type shares (the site, the other robots, the path under traffic grants) is its
/// Navigation; what differs (the body, the sensors, the job) is the type's own.
/// robot::make_robot (robot_factory.hpp) builds the one a fleet's `robot_type` names.
class Robot {
 public:
  virtual ~Robot() = default;

  // --- orders ---------------------------------------------------------------------------------
  /// Why this type cannot perform orders of `kind` at all; empty when it can.
  virtual std::string refusal(orders::OrderKind kind) const = 0;
  /// An order; false with the reason when the robot cannot take it now.
  virtual bool submit(const task::TaskOrder& order, std::string* why) = 0;
  /// The server took the order away: drop it and go home. False, with the order left running,
  /// when the robot cannot stop it now (a load half taken up).
  virtual bool withdraw() = 0;
  virtual void set_paused(bool paused) = 0;
  /// Where to drop the load of a transport submitted without its drop place (a VDA 5050 master
  /// sends the pick and the drop as orders of their own). False when the robot runs no such
  /// transport, or its type takes a transport only whole.
  virtual bool set_drop(const std::string& area_id, const geometry::Pose2& area) {
    (void)area_id;
    (void)area;
    return false;
  }

  // --- the world as the agent hears it --------------------------------------------------------
  /// The server switched this robot to a revision of its site's map (see map::revision_mismatch);
  /// `route_graph` is the graph to plan on, null for the site's own.
  virtual void set_site(std::shared_ptr<const map::SiteMap> site,
                        std::shared_ptr<const map::RoadGraph> route_graph) = 0;
  /// A designated static obstacle switched on or off. True when the robot is driving and asked
  /// for a new plan on the changed grid.
  virtual bool set_obstacle(const std::string& id, bool enabled) = 0;
  /// Where the loads really stand (simulation truth, owned by the server), by id; loads carried
  /// by other robots are left out.
  virtual void set_standing_loads(const std::map<int, geometry::Pose2>& standing) = 0;
  /// The traffic manager's latest grant for this robot (traffic on only).
  virtual void set_traffic_grant(const TrafficPermit& permit) = 0;
  /// The site, the other robots (Navigation::set_neighbours, set_true_neighbours) and the path
  /// being followed (navigation().follower()), as every type has them.
  virtual Navigation& navigation() = 0;
  virtual const Navigation& navigation() const = 0;

  // --- time -----------------------------------------------------------------------------------
  /// One control step of step_period() sim seconds.
  virtual void step() = 0;
  virtual double step_period() const = 0;
  /// Sim seconds since the robot started, as status().time: the clock the agent steps it by, read
  /// every step without building a whole status.
  virtual double time() const = 0;

  // --- what it reports ------------------------------------------------------------------------
  virtual RobotStatus status() const = 0;
  virtual std::vector<RobotEvent> take_events() = 0;
  /// The route to report to the traffic manager, with the progress along it.
  virtual TrafficRoute traffic_route() const = 0;
  /// The docking under way; empty when none (and for types that do not dock).
  virtual DockingView docking_view() const { return {}; }
};

}  // namespace fleet::robot
