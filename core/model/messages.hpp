#pragma once

// Plain C++ values of what crosses the wire, one struct per DDS topic (idl/fleet.idl). core/,
// server/, agent/ and cli/ work with these; only dds/ knows the IDL's C structs.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "geometry/polygon.hpp"

namespace fleet::model {

struct ServerInfo {
  std::string server_id;
  std::string site;
  std::vector<std::string> loading_areas;
  std::vector<std::string> robots;
  std::vector<std::string> obstacles;
  std::vector<std::string> maps;
  double time_scale = 1.0;
  std::int64_t started_unix_ms = 0;
  std::vector<std::string> homes;  ///< parking places, where a move order may go too
  /// Robots' own messages the server refused: their writer may not speak for the robot they name
  /// (model::judge_sender).
  std::int64_t refused_samples = 0;
  std::vector<std::string> refused_senders;  ///< each refused writer once, described
};

struct OrderRequest {
  std::string request_id;
  std::string pick_area;
  std::string drop_area;
  std::string fleet_id;  ///< empty: the server chooses
  std::string robot_id;  ///< empty: the server chooses
  int priority = 0;
  std::string kind;   ///< orders::OrderKind name; empty: transport
  std::string lines;  ///< pick: the pick list as CSV, place,item,quantity per line
  /// pick: how its boxes travel (orders::parse_handling): tray (to a packing station), loader
  /// (onto a transporter's pallet behind the picker, docs/loader.md) or auto; empty: tray.
  std::string handling{};
};

struct Command {
  std::string request_id;
  std::string verb;  ///< cancel-order, obstacle, map, pause, resume, auto-orders
  std::string target;
  std::string value;
  std::uint32_t update_id = 0;
};

struct RequestReply {
  std::string request_id;
  bool accepted = false;
  std::int64_t order_id = 0;  ///< the first order created
  std::string error;
  int order_count = 0;  ///< orders created: ids order_id to order_id + order_count - 1
};

/// An order as sent to its robot.
struct OrderAssignment {
  std::int64_t order_id = 0;
  std::string robot_id;
  std::string pick_area;
  geometry::Pose2 pick_pose;  ///< the loading area's pose (see map::LoadingArea)
  std::string drop_area;
  geometry::Pose2 drop_pose;
  std::uint32_t update_id = 0;
  bool cancelled = false;
  std::string kind;   ///< orders::OrderKind name; a move drives to drop_area / drop_pose and stays
  std::string lines;  ///< pick: the tour's lines as CSV, place,item,quantity, in driving order
  /// Pick: a loader's walk (docs/loader.md), each stop's boxes onto the pallet of the transporter
  /// behind the robot; the order ends at the last stop.
  bool loader = false;
  std::uint32_t released_stops = 0;  ///< loader: the arm works the first released_stops stops only
  /// loader: it may drive to the first approach_stops stops; at one not released it waits to load
  std::uint32_t approach_stops = 0;
  int pallet = 0;  ///< loader: which transporter's pallet stands behind it
  /// A transport with no drop area yet: where to stand with the load meanwhile (the body's centre).
  std::optional<geometry::Pose2> stand{};
};

/// An agent's report on its order.
struct OrderReport {
  std::int64_t order_id = 0;
  std::string robot_id;
  std::string status;  ///< ACCEPTED, REJECTED, a phase name, DONE, FAILED
  std::string reason;
  std::uint32_t update_id = 0;
  double sim_time = 0.0;
  bool carrying_pallet = false;
  int pallet_id = -1;           ///< the pallet on the forks, or put down on DONE
  geometry::Pose2 pallet_pose;  ///< on DONE: where the pallet really stands
};

/// Simulation truth of a pallet, owned by the server.
struct PalletTruth {
  int pallet_id = 0;
  geometry::Pose2 pose;
  std::string area_id;     ///< loading area it stands on; empty when carried or astray
  std::string carried_by;  ///< robot id; empty when standing
};

struct OrderEvent {
  double sim_time = 0.0;
  std::string state;
  std::string phase;
  std::string robot_id;
  std::string reason;
  double robot_x = 0.0;
  double robot_y = 0.0;
};

/// The server's view of an order's lifecycle.
struct OrderInfo {
  std::int64_t order_id = 0;
  std::string request_id;
  std::string pick_area;
  std::string drop_area;
  std::string fleet_id;
  std::string robot_id;
  std::string state;  ///< QUEUED, ASSIGNED, ACTIVE, DONE, FAILED, CANCELLED
  std::string phase;
  std::string reason;
  int priority = 0;
  double created_sim = 0.0;
  double updated_sim = 0.0;
  std::vector<OrderEvent> history;      ///< oldest first, at most kMaxOrderHistory
  std::string kind;                     ///< orders::OrderKind name
  std::string cause;                    ///< why the server created it itself (orders::Order::cause)
  std::vector<std::int64_t> caused_by;  ///< the orders it follows from
  std::string lines;                    ///< a pick order's tour (orders::Order::lines)
  bool robot_requested = false;         ///< robot_id was asked for, not chosen by dispatch
  std::uint32_t update_id = 0;
  double assigned_sim = 0.0;
  double finished_sim = 0.0;
  bool loader = false;  ///< orders::Order::loader
};

inline constexpr std::size_t kMaxOrderHistory = 64;

/// An order a server that stepped down hands over to the active one: its version of the order, on
/// a topic of its own (fleet/OrderHandover, the wire type of OrderInfo) that every server writes
/// and the active one reads.
struct OrderHandover : OrderInfo {
  OrderHandover() = default;
  OrderHandover(OrderInfo info) : OrderInfo(std::move(info)) {}  // implicit: read back from the wire as one
};

/// RobotState::detail of a loader waiting, by design, for its transporter to stand behind its
/// next stop (docs/loader.md): it waits for its partner, not for traffic.
inline constexpr const char* kDetailWaitsForTransporter = "waiting for its transporter behind the next stop";

struct RobotState {
  std::string robot_id;
  std::string fleet_id;
  std::string map_id;
  geometry::Pose2 pose;
  std::array<double, 9> covariance{};  ///< x, y, yaw; row-major
  double localization_score = 1.0;
  double speed = 0.0;
  double yaw_rate = 0.0;
  std::string task_state;
  std::string detail;
  std::int64_t order_id = 0;
  bool carrying_pallet = false;
  double sim_time = 0.0;
  /// A picker on a loader walk (docs/loader.md): the stop it stands at (-1 while it drives or
  /// has none), and the boxes its arm has set on transporters' pallets in the order so far.
  int walk_stop = -1;
  int boxes_loaded = 0;
  /// While the robot docks (a stacker): where its rear axle is steered to before the final
  /// approach, target 1 then target 2, and the pallet its cameras detect (centre and entry-axis
  /// yaw), in the frame of `pose`. Empty otherwise.
  std::vector<geometry::Vec2> docking_targets;
  std::optional<geometry::Pose2> detected_pallet;
  /// How late the agent's control steps run against the clock since it started (StepLagMeter),
  /// seconds of sim time; its control period; steps it jumped over after falling far behind.
  double control_lag_p50 = 0.0;
  double control_lag_p99 = 0.0;
  double control_period = 0.0;
  std::int64_t control_steps_skipped = 0;
};

struct RobotPath {
  std::string robot_id;
  std::vector<geometry::Vec2> points;
  double sim_time = 0.0;
};

struct RobotControl {
  std::string robot_id;
  bool paused = false;
};

struct MapAssignment {
  std::string robot_id;
  std::string map_id;
};

struct StaticObstacleState {
  std::string obstacle_id;
  std::string map_id;
  bool enabled = false;
  geometry::Polygon polygon;
};

struct RobotSnapshot {
  std::string robot_id;
  std::string fleet_id;
  geometry::Pose2 pose;
  geometry::Footprint footprint;
  double speed = 0.0;
  std::string task_state;
  double sim_time = 0.0;
  std::vector<geometry::Vec2> path;
};

struct FleetView {
  std::string map_id;
  double sim_time = 0.0;
  std::vector<RobotSnapshot> robots;
};

/// Simulation only: a robot's true pose and footprint (idl/fleet.idl SimTruth).
struct SimTruth {
  std::string robot_id;
  geometry::Pose2 pose;
  geometry::Footprint footprint;
  bool carrying_pallet = false;
  double sim_time = 0.0;
};

/// The robots within `radius` of one robot, for its agent alone (idl/fleet.idl NeighbourView).
struct NeighbourView {
  std::string robot_id;
  std::string map_id;
  double sim_time = 0.0;
  double radius = 0.0;
  bool complete = true;
  std::vector<RobotSnapshot> robots;
  /// Simulation only: the true bodies near it, from the SimTruth the server hears (its sensors see these).
  std::vector<SimTruth> bodies;
};

/// The DDS partition of the messages meant for one robot's agent alone.
inline std::string robot_partition(const std::string& robot_id) {
  return "robot." + robot_id;
}

/// Every robot's partition at once (a wildcard): for the readers that watch the whole fleet.
inline std::string every_robot_partition() {
  return "robot.*";
}

/// An agent's road-graph route and its progress along it, for traffic control. Empty `points`: the
/// robot is off the roads and holds nothing.
struct TrafficRequest {
  std::string robot_id;
  std::uint64_t version = 0;
  std::vector<int> points;
  double progress = 0.0;  ///< metres from the route's first point
  /// Robots whose bodies the robot's safety check has kept it standing for a while (see
  /// traffic::ProgressReport::stopped_for).
  std::vector<std::string> stopped_for;
  double sim_time = 0.0;
  /// Off the roads (`points` empty): the area a manoeuvre beside the roads sweeps (docking in
  /// reverse, parking), as points whose convex hull it is, map frame; empty when it only stands. The server answers
  /// AREA_CLEAR once no other robot holds a place it touches, and holds it for the robot from then on.
  geometry::Polygon work_area;
  /// On a route: the area the robot sweeps turning off the route's last point into a place beside
  /// the road, as points whose convex hull it is, map frame; empty when it sweeps nothing beyond
  /// the lane (traffic::TrafficManager::set_arrival_area).
  geometry::Polygon arrival_area;
  /// Off the roads, standing with its body reaching onto them (a stacker docked at a pallet
  /// place): the area it will sweep turning out onto the road, to either side, when it leaves, as
  /// points whose convex hull it is. No other robot is granted to stop in it meanwhile
  /// (traffic::TrafficManager::keep_clear); empty when it asks for nothing.
  geometry::Polygon keep_clear;
  /// The map whose road graph numbers `points`. A request for another map than the server's was
  /// sent before the robot heard of a map switch: the server ignores it.
  std::string map_id;
};

/// How far along route `version` of its last TrafficRequest a robot has driven: sent at the state
/// rate between TrafficRequests, which carry the route only when it changes (and once a second).
struct TrafficProgress {
  std::string robot_id;
  std::uint64_t version = 0;
  double progress = 0.0;  ///< metres from the route's first point
  std::vector<std::string> stopped_for;
  double sim_time = 0.0;
  std::string map_id;
};

/// The server's traffic grant for one robot (see traffic::Grant).
struct TrafficGrant {
  std::string robot_id;
  std::uint64_t version = 0;
  int granted_index = 0;
  double granted_distance = 0.0;
  std::string status;  ///< MOVING, WAITING, ARRIVED; AREA_CLEAR, AREA_WAITING (TrafficRequest::work_area)
  double waited_s = 0.0;
  std::vector<std::string> blocked_by;
  std::string instruction;  ///< empty, REROUTE or SIDING
  std::vector<int> route;
  double sim_time = 0.0;
};

/// What the server's own work costs, since it started (idl/fleet.idl ServerLoad).
struct ServerLoad {
  std::string server_id;
  double sim_time = 0.0;
  int robots = 0;
  std::int64_t traffic_cycles = 0;
  double traffic_cycle_p50_ms = 0.0;
  double traffic_cycle_p99_ms = 0.0;
  double traffic_cycle_max_ms = 0.0;
  double traffic_update_p50_ms = 0.0;  ///< the update alone: every robot's grant decided
  double traffic_update_p99_ms = 0.0;
  double traffic_update_max_ms = 0.0;
  std::int64_t dispatches = 0;
  double dispatch_p50_ms = 0.0;
  double dispatch_p99_ms = 0.0;
  double dispatch_max_ms = 0.0;
  std::int64_t term = 0;  ///< the term it serves in (active) or last heard served (standby)
  bool active = false;
  bool took_over = false;           ///< active: it became active by taking over from another server
  std::int64_t since_unix_ms = 0;   ///< active: since it took its term; standby: since it began to mirror
  double active_heard_s_ago = 0.0;  ///< standby: wall seconds since it last heard the active server
};

/// The site's state as the server stores it (orders::to_json of orders::SiteState).
struct SiteStateDocument {
  std::string site;
  std::string json;
};

}  // namespace fleet::model
