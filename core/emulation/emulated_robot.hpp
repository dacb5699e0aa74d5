#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "map/road_graph.hpp"
#include "orders/order_kind.hpp"
#include "planning/grid_planner.hpp"
#include "planning/road_planner.hpp"
#include "planning/route_planner.hpp"
#include "robot/robot.hpp"
#include "robot/traffic_follower.hpp"

namespace fleet::emulation {

/// The off-road legs of an emulated robot's routes: one straight segment from the pose to the
/// road point and from the road point to the goal. An emulated robot has no map of its
/// surroundings; the sites it drives park homes and loading areas beside the roads.
class StraightLegs : public planning::GridPlanner {
 public:
  std::string name() const override { return "straight_legs"; }
  void set_grid(std::shared_ptr<const planning::OccupancyGrid>) override {}
  planning::GridPath plan(geometry::Vec2 start, geometry::Vec2 goal, const planning::PlanOptions&) override;
};

/// Route planning shared by every emulated robot of one vehicle type: road A* on the type's
/// route graph (the traffic manager's, one-way corridors included) with straight legs off it.
class EmulatedRoutes {
 public:
  explicit EmulatedRoutes(std::shared_ptr<const map::RoadGraph> graph);
  planning::Route plan(const geometry::Pose2& from, const geometry::Pose2& to);
  const map::RoadGraph& graph() const { return *graph_; }

 private:
  std::shared_ptr<const map::RoadGraph> graph_;
  planning::RoadPlanner road_;
  StraightLegs legs_;
  planning::RoutePlanner routes_;
};

/// An order as an emulated robot runs it.
struct EmulatedOrder {
  std::int64_t id = 0;
  orders::OrderKind kind = orders::OrderKind::kTransport;
  std::string pick_area;
  geometry::Pose2 pick_pose;
  std::string drop_area;
  geometry::Pose2 drop_pose;
  int load_id = -1;  ///< transport: the load standing at the pick area, taken up there
};

struct EmulatedEvent {
  enum class Kind { kPhase, kDone, kHome };
  Kind kind = Kind::kPhase;
  std::int64_t order_id = 0;
  std::string phase;  ///< kPhase: TO_PICK, PICKING, TO_DROP, DROPPING
  int load_id = -1;   ///< kDone of a transport: the load put down, at `load_pose`
  geometry::Pose2 load_pose;
};

struct EmulationParams {
  double speed = 1.0;    ///< m/s along the path, from standstill at once
  double dwell_s = 5.0;  ///< sim seconds taking up or putting down a load
  double step_s = 0.05;  ///< sim seconds per step
  double retry_s = 2.0;  ///< sim seconds before a route that could not be planned is asked again
  double siding_timeout_s = 30.0;
};

/// A load generator's robot: a body that drives its route kinematically at its speed, only as far
/// as the traffic manager grants (robot::TrafficFollower, as every agent), and runs transport and
/// move orders through the phases an agent reports. No sensors, no localization, no safety stop:
/// its pose is exact. It stands in for an agent only in `fleetctl load`, to load a real server.
class EmulatedRobot {
 public:
  EmulatedRobot(std::string id, const geometry::Pose2& home, const EmulationParams& params,
                std::uint64_t first_route_version);

  /// Takes an order; the reason when it cannot (busy, a kind it does not do).
  std::string submit(const EmulatedOrder& order);
  /// Drops the order and goes home; false when a load is on board (the order goes on).
  bool withdraw();
  void grant(const robot::TrafficPermit& permit);
  /// One step of params.step_s at sim time `now`.
  void step(double now, EmulatedRoutes& routes);

  std::vector<EmulatedEvent> take_events();
  const std::string& id() const { return id_; }
  const geometry::Pose2& pose() const { return pose_; }
  double speed() const { return speed_; }
  /// IDLE, TRACK_PATH, PICK_PALLET, DROP_PALLET, GO_HOME, WAITING: the agent's names.
  std::string task_state() const;
  const std::optional<EmulatedOrder>& order() const { return order_; }
  int carried_load() const { return carried_; }
  const std::vector<geometry::Vec2>& path() const { return follower_.path(); }
  robot::TrafficRoute traffic_route() const { return follower_.route(); }
  std::uint64_t route_version() const { return follower_.version(); }

 private:
  enum class Stage { kIdle, kToPick, kPicking, kToDrop, kDropping, kHoming };
  void start_leg(Stage stage, const geometry::Pose2& goal);
  void arrived(double now);
  void drive(double now);
  void phase(const std::string& name);

  std::string id_;
  geometry::Pose2 home_;
  EmulationParams params_;
  geometry::Pose2 pose_;
  double speed_ = 0.0;
  Stage stage_ = Stage::kIdle;
  std::optional<EmulatedOrder> order_;
  int carried_ = -1;
  geometry::Pose2 goal_;
  bool needs_plan_ = false;
  double plan_after_ = 0.0;
  double dwell_until_ = 0.0;
  bool held_ = false;
  robot::TrafficFollower follower_;
  std::vector<double> path_cum_;
  double path_s_ = 0.0;
  std::vector<EmulatedEvent> events_;
};

}  // namespace fleet::emulation
