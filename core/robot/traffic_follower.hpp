#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/pose.hpp"
#include "map/road_graph.hpp"
#include "model/messages.hpp"
#include "planning/route_planner.hpp"
#include "robot/robot.hpp"

namespace fleet::robot {

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

/// What the server's grant (model::TrafficGrant, idl/fleet.idl) tells the robot it is for.
TrafficPermit permit_of(model::TrafficGrant grant);

struct TrafficFollowerParams {
  /// Traffic control: report the road part of every route and drive only as far as the server
  /// grants. Off: every grant is ignored and the room is unlimited.
  bool traffic = false;
  /// Sim seconds a robot stands held on a siding before it plans its own way on and asks for it.
  double siding_timeout = 30.0;
  double siding_end_margin = 0.03;  ///< metres short of a siding's end the robot stops
  /// Off the road (at a dock, in a bay), stand until the grant reaches past the road's first
  /// point. A body that turns onto the lane from across it (a stacker leaving a dock) would stand
  /// at that point across the lane's edge, in the way of robots passing beside, while it waits.
  bool wait_off_road_for_room = false;
};

/// The path a robot drives and what traffic control makes of it, for every robot type: the road
/// part reported to the traffic manager (TrafficRoute), the grants it drives by, the manager's
/// re-routes and sidings, and route versions. The path's arc length is the common measure: the
/// road part starts at `road_start_` and its graph points sit at `road_start_ + road_cum_[i]`.
class TrafficFollower {
 public:
  /// The first version is taken from the wall clock (first_route_version).
  explicit TrafficFollower(TrafficFollowerParams params);
  TrafficFollower(TrafficFollowerParams params, std::uint64_t first_version);

  /// A plan of the robot's own: its points become the path, its road part the route, under the
  /// next own version when it has one.
  void adopt_plan(const planning::Route& route);
  /// A route the manager handed over (TrafficPermit::route, points of `graph`), joined from the
  /// robot at `here`; a route back to the own plan's last road point keeps that plan's leg off
  /// the road to the goal.
  void adopt_route(const TrafficPermit& permit, const map::RoadGraph& graph, geometry::Vec2 here);
  /// No path for now (a plan failed); the route stays reported.
  void drop_path() { path_.clear(); }
  /// Arrived beside the road (a goal, home): no path and no road held any more.
  void leave_road();
  /// Another map: its manager knows nothing of the old route or grants.
  void forget_route();

  /// The manager's latest grant. True when it hands over a new route: the robot must plan again
  /// and take it with take_route().
  bool grant(const TrafficPermit& permit);
  /// The re-route waiting for the next plan, once.
  std::optional<TrafficPermit> take_route();

  /// Where the controller that drives the path is along it: a path of this length whose leg
  /// being followed begins `leg_start_s` metres from its start. On a path over the same ground
  /// twice, the controller decides which pass the robot is on; where it sits says nothing.
  struct ControllerLeg {
    double path_length = 0.0;
    double leg_start_s = 0.0;
  };
  /// Metres the robot at `here` may still drive along its path before the end of its grant:
  /// infinite when traffic is off, off the road or granted all the way; negative before the
  /// first grant of a route, so it stands (not even turning) until admitted. `leg` (when it is of
  /// this path) says which leg the robot is on; without it, a cusp counts as passed once the
  /// robot is within 3 cm of it.
  double room(geometry::Vec2 here, std::optional<ControllerLeg> leg = std::nullopt);
  /// Metres along the path up to which the latest grant lets the robot drive, wherever it stands:
  /// infinite when traffic is off, off the road or granted all the way; nothing before the first
  /// grant of the route. room() is this less where the robot is.
  std::optional<double> granted_end() const;
  /// Once a step with whether the robot stands `held` by traffic at sim time `t`. True when it
  /// has stood on its siding longer than siding_timeout with nobody calling it back (a manager
  /// restarted meanwhile has no record of the siding): it has left the siding, and the caller
  /// plans its way on as a route of its own.
  bool siding_timed_out(double t, bool held);

  const std::vector<geometry::Vec2>& path() const { return path_; }
  /// On a path that backs up and comes back over the same ground, the segment the robot was last
  /// found on (room()); nothing on a path without cusps, where the nearest segment is the one.
  std::optional<std::size_t> segment_on_leg() const;
  /// The route for the traffic manager, without `stopped_for` (the safety stop's to add).
  TrafficRoute route() const;
  std::uint64_t version() const { return version_; }
  bool on_road() const { return !road_points_.empty(); }
  /// Metres of path before the road part starts: the way from beside the road onto it.
  double road_start() const { return road_start_; }
  /// Metres of path where the road part ends: beyond it the path leads off the road to the goal.
  double road_end() const { return road_cum_.empty() ? road_start_ : road_start_ + road_cum_.back(); }
  /// Still on the way onto the road, where it was last found (room()).
  bool before_road() const { return on_road() && path_s_ < road_start_; }
  bool in_siding() const { return in_siding_; }
  /// Who holds the road ahead, as the latest grant says.
  const std::vector<std::string>& blocked_by() const { return permit_.blocked_by; }

 private:
  double path_position(geometry::Vec2 here, std::optional<ControllerLeg> leg) const;

  TrafficFollowerParams params_;
  std::vector<geometry::Vec2> path_;
  std::vector<double> path_cum_;    ///< metres from the path's start to each point
  std::vector<double> path_cusps_;  ///< metres from the path's start to each cusp
  double path_s_ = 0.0;             ///< where the robot was last found along the path
  std::uint64_t version_ = 0;
  std::vector<int> road_points_;
  std::vector<double> road_cum_;
  double road_start_ = 0.0;
  bool in_siding_ = false;
  double siding_held_since_ = -1.0;  ///< sim time it was first held on its siding, -1 when not
  TrafficPermit permit_;
  std::optional<TrafficPermit> pending_route_;  ///< an instruction to adopt at the next plan
  /// The last road point of this robot's own plan and the path after it (off the road to the
  /// goal or home): kept through the manager's re-routes and sidings, so a route that comes back
  /// to that point still ends where the task needs the robot.
  int goal_point_ = -1;
  std::vector<geometry::Vec2> goal_leg_;
};

}  // namespace fleet::robot
