#pragma once
// How one of Fleet's robots carries out a VDA 5050 order a master control sent it: where its
// nodes are on the site, which job (a move or a transport) the robot runs for it, and how far
// along its route the order's base lets it drive.

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "map/road_graph.hpp"
#include "map/site.hpp"
#include "robot/robot.hpp"
#include "task/task_executor.hpp"
#include "vda5050/vehicle_order.hpp"

namespace fleet::vda5050 {

/// Where a node of an order is on the site: a point of the road graph or a place beside the
/// roads (a loading area or a home).
struct NodeOnSite {
  std::uint32_t sequence = 0;
  bool released = false;
  int point = -1;     ///< graph point id; -1 at a place
  std::string place;  ///< loading area or home id; empty on a graph point
  geometry::Pose2 pose;
};

/// Locates `node`: by its id when it names a graph point (`p<id>`), a loading area or a home;
/// else by its position, on the nearest graph point or place within the node's allowed deviation
/// (5 cm when it gives none), else as a waypoint of the master's own path off the roads (no
/// point, no place), which the robot passes on its own way. Nothing, and `why` says so, for a
/// node without a position that names nothing of the site, or one outside the site.
std::optional<NodeOnSite> locate_node(const ReceivedNode& node, const map::Site& site, const map::RoadGraph& graph,
                                      std::string* why);

/// The job a robot runs for the nodes ahead of it: a move to the last node, or a transport
/// picking at the node of a `pick` action and dropping at the node of the `drop` that follows.
/// A pick alone is a transport whose drop comes with a later order (drop_action empty); a drop
/// alone, the rest of the transport of a robot that carries the load (pick_action empty).
struct VehicleJob {
  task::TaskOrder order;
  std::string pick_action;  ///< action ids; empty for a move
  std::string drop_action;
  std::uint32_t pick_node = 0;  ///< sequence ids
  std::uint32_t goal_node = 0;  ///< where the job ends: the drop, or the move's place
  std::vector<NodeOnSite> nodes;
};

/// The job for `nodes` (the order's nodes ahead, base and horizon), or the orderError (naming the
/// action) or noRouteError (naming the node) that rejects the order. Actions are `pick` and `drop`
/// at loading areas, only for a robot that transports (`transports`); a transport ends at its drop.
/// `carrying`: the robot holds the load of a pick already done, so a drop needs no pick before it.
std::variant<VehicleJob, VehicleError> job_of(const std::string& order_id, const std::vector<ReceivedNode>& nodes,
                                              const std::vector<ReceivedEdge>& edges, const map::Site& site,
                                              const map::RoadGraph& graph, bool transports, bool carrying,
                                              const nlohmann::json& message);

/// The shortest way along `graph` from point `from` to point `to` (both included), empty when
/// there is none.
std::vector<int> shortest_road(const map::RoadGraph& graph, int from, int to);

/// Turns the order's base into traffic grants for the robot (robot::TrafficPermit), as the
/// traffic manager would: the route the robot planned is led through the order's road nodes (a
/// re-route when its own plan misses them), and granted up to the last released node of the leg
/// it drives. Which nodes the robot has passed follows from its progress along that route.
class VehicleDrive {
 public:
  /// A new job or a changed base: `leg` is the nodes ahead up to the end of the leg being driven
  /// (the pick, then the drop; the whole order for a move).
  void set_leg(std::vector<NodeOnSite> leg) { leg_ = std::move(leg); }
  /// The permit for the route the robot reports now; nothing while it has no road route or the
  /// base lets it no further than where it stands.
  std::optional<robot::TrafficPermit> permit(const robot::TrafficRoute& route, const map::RoadGraph& graph);
  /// The sequence ids of the leg's road nodes the robot has passed along its route, in order.
  std::vector<std::uint32_t> passed(const robot::TrafficRoute& route) const;

 private:
  struct Led {
    std::uint64_t own_version = 0;  ///< the robot's plan; own_version + 1 is the route handed over
    std::vector<int> route;
    std::vector<std::pair<std::uint32_t, double>> node_at;  ///< road node sequence -> metres along the route
    std::vector<double> along;                              ///< metres along the route to each of its points
  };
  /// Leads the robot's own route through the leg's road nodes.
  Led lead(const robot::TrafficRoute& route, const map::RoadGraph& graph) const;

  std::vector<NodeOnSite> leg_;
  std::optional<Led> led_;
};

}  // namespace fleet::vda5050
