#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "emulation/emulated_robot.hpp"
#include "geometry/pose.hpp"
#include "orders/order_kind.hpp"
#include "robot/robot.hpp"
#include "robot/traffic_follower.hpp"
#include "vda5050/messages.hpp"
#include "vda5050/order_release.hpp"

namespace fleet::vda5050 {

/// A Fleet order as the master runs it on a VDA 5050 vehicle.
struct MasterOrder {
  std::int64_t id = 0;
  orders::OrderKind kind = orders::OrderKind::kTransport;
  std::string pick_area;
  geometry::Pose2 pick_pose;
  std::string drop_area;
  geometry::Pose2 drop_pose;
  int load_id = -1;  ///< transport: the load standing at the pick area
};

/// What the master tells the server of the order: a phase (TO_PICK, PICKING, TO_DROP, DROPPING,
/// MOVING), DONE or FAILED with the vehicle's reason.
struct MasterEvent {
  enum class Kind { kPhase, kDone, kFailed };
  Kind kind = Kind::kPhase;
  std::int64_t order_id = 0;
  std::string phase;
  std::string reason;
  int load_id = -1;  ///< kDone of a transport: the load put down, at `load_pose`
  geometry::Pose2 load_pose;
};

/// A message for the vehicle: `name` is its topic's last part (order, instantActions).
struct Outgoing {
  std::string name;
  nlohmann::json body;
};

/// Fleet as master control of one VDA 5050 vehicle [VDA 5050, section 5]: it plans each leg of a
/// Fleet order on the site's roads as any robot does, reports the leg's road part to traffic
/// control and releases to the vehicle only the nodes traffic control has granted (base), the
/// rest as horizon; each further grant is an order update. The vehicle's state is its pose and
/// progress. Pure decisions: the caller carries the messages over MQTT and DDS.
class VehicleMaster {
 public:
  /// `version`: the VDA 5050 version the vehicle speaks (2.0.0, 2.1.0).
  VehicleMaster(std::string robot_id, std::string version, std::string map_id, std::string home_id,
                const geometry::Pose2& home, std::uint64_t first_route_version);

  /// Takes an order; the reason when it cannot (busy, a kind it does not do).
  std::string submit(const MasterOrder& order);
  /// Drops the order (cancelOrder to the vehicle) and goes home; false when a load is on board.
  bool withdraw();
  void grant(const robot::TrafficPermit& permit);
  /// The vehicle's state. One that says its position is not initialised is told where it parks:
  /// `initPosition` with its home's pose and node, once each time it says so [VDA 5050, section
  /// 6.8.1].
  void take_state(const VehicleState& state);
  /// An instant action without parameters for the vehicle: stateRequest, factsheetRequest.
  void request(const std::string& type);
  /// The operator pauses or resumes the robot: startPause / stopPause to the vehicle, once each
  /// change [VDA 5050, section 6.7].
  void set_paused(bool paused);
  bool paused() const { return paused_; }
  /// The vehicle is back after it was lost: whatever it knew of its order is gone (a restart) or
  /// stale. Messages not yet sent are dropped; the leg under way is planned and sent again.
  void reconnected();
  /// A position between states (the vehicle's `visualization`): pose and speed only.
  void take_position(const VehicleState& position);
  /// Plans, releases and follows the vehicle; call after the messages of a cycle are taken.
  void step(emulation::EmulatedRoutes& routes);

  std::vector<Outgoing> take_messages();
  std::vector<MasterEvent> take_events();

  const std::string& id() const { return id_; }
  bool has_state() const { return state_.has_value(); }
  const geometry::Pose2& pose() const { return pose_; }
  double speed() const { return state_ ? state_->speed : 0.0; }
  /// IDLE, TRACK_PATH, PICK_PALLET, DROP_PALLET, GO_HOME, WAITING, PAUSED: the agent's names.
  std::string task_state() const;
  const std::optional<MasterOrder>& order() const { return order_; }
  int carried_load() const { return carried_; }
  const std::vector<geometry::Vec2>& path() const { return follower_.path(); }
  robot::TrafficRoute traffic_route() const { return follower_.route(); }
  std::uint64_t route_version() const { return follower_.version(); }
  /// The vehicle's latest error of level FATAL or WARNING, "" when none.
  const std::string& last_error() const { return last_error_; }
  /// The VDA 5050 order of the current leg, nothing between legs.
  const std::optional<ReleasedOrder>& leg_order() const { return leg_; }

 private:
  enum class Stage { kIdle, kToPick, kToDrop, kHoming };
  void start_leg(Stage stage, const geometry::Pose2& goal, std::string goal_id);
  bool vehicle_stands_ready() const;
  void plan_leg(emulation::EmulatedRoutes& routes);
  std::vector<OrderNode> leg_nodes(const map::RoadGraph& graph, std::vector<double>& node_s) const;
  void release();
  void follow_leg();
  void arrived();
  void fail(const std::string& reason);
  void phase(const std::string& name);
  /// Queues an instant action of `type` for the vehicle, its id made of the robot id, `tag` and a count.
  void instant(const std::string& type, const std::string& tag,
               const std::vector<std::pair<std::string, nlohmann::json>>& parameters = {});

  std::string id_;
  std::string version_;
  std::string map_id_;
  std::string home_id_;
  geometry::Pose2 home_;
  geometry::Pose2 pose_;
  std::optional<VehicleState> state_;
  Stage stage_ = Stage::kIdle;
  std::optional<MasterOrder> order_;
  int carried_ = -1;
  geometry::Pose2 goal_;
  std::string goal_id_;
  bool needs_plan_ = false;
  bool held_ = false;
  bool paused_ = false;
  std::uint32_t instant_actions_ = 0;
  bool init_position_sent_ = false;  ///< since it last said its position is not initialised
  bool phase_at_goal_sent_ = false;
  std::optional<ReleasedOrder> leg_;
  std::uint32_t legs_ = 0;
  robot::TrafficFollower follower_;
  std::string last_error_;
  std::vector<std::string> reported_errors_;
  std::vector<Outgoing> messages_;
  std::vector<MasterEvent> events_;
};

}  // namespace fleet::vda5050
