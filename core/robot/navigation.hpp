#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "map/site_map.hpp"
#include "planning/grid_astar.hpp"
#include "planning/lidar_sim.hpp"
#include "planning/road_planner.hpp"
#include "planning/route_planner.hpp"
#include "planning/static_grid.hpp"
#include "robot/robot.hpp"
#include "robot/safety_stop.hpp"
#include "robot/traffic_follower.hpp"

namespace fleet::robot {

struct NavigationParams {
  double grid_resolution = 0.02;  ///< static grid of the legs off the roads, metres
  /// The graph routes are planned on (the traffic manager's graph for the vehicle type); null:
  /// the site's road graph.
  std::shared_ptr<const map::RoadGraph> route_graph;
  /// When the route graph has no way (a static obstacle closes every way along a one-way
  /// corridor), plan on the site's graph in both directions: the traffic manager keeps opposite
  /// directions apart in a corridor.
  bool both_ways_when_closed = false;
  planning::RoutePlannerConfiguration routes;
  planning::LidarConfiguration lidar;
  TrafficFollowerParams follower;
  SafetyStopParams safety;
};

/// What every robot type runs between its body and its job: the site with its static grid and
/// the state of its switchable obstacles, the route planners on it, the other robots as reported
/// (for the look ahead and the safety stop) and as the onboard lidar sees them, the route
/// followed under traffic grants (TrafficFollower) and the safety stop (SafetyStop). A robot
/// type holds one and adds its body, sensors and job.
class Navigation {
 public:
  Navigation(NavigationParams params, std::shared_ptr<const map::SiteMap> site, const geometry::Footprint& footprint);
  // The planners keep references into this object.
  Navigation(const Navigation&) = delete;
  Navigation& operator=(const Navigation&) = delete;

  // --- the site -------------------------------------------------------------------------------
  /// A new map: grid, obstacles (as the site sets them at the start) and planners from it, the
  /// route forgotten (it means nothing to the traffic of the new map).
  void set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph);
  const map::SiteMap& site() const { return *site_; }
  /// Switches a static obstacle of the site; false when the site has none of that id or it is
  /// already so (nothing to replan).
  bool set_obstacle(const std::string& id, bool enabled);
  /// The static grid, for temporaries of the local planner.
  planning::StaticGrid& static_grid() { return static_grid_; }
  const planning::StaticGrid& static_grid() const { return static_grid_; }
  /// Whether the site's static obstacle `id` is switched on.
  bool obstacle_enabled(const std::string& id) const { return obstacles_.at(id); }
  /// The enabled static obstacles' polygons.
  std::vector<geometry::Polygon> enabled_obstacles() const;

  // --- planning -------------------------------------------------------------------------------
  /// A route from `from` to `goal` on the route graph (both ways on the site's graph when
  /// both_ways_when_closed and the route graph has none), on the static grid as it is now.
  planning::Route plan(const geometry::Pose2& from, const geometry::Pose2& goal);

  // --- the other robots -----------------------------------------------------------------------
  void set_neighbours(std::vector<Neighbour> neighbours) { neighbours_ = std::move(neighbours); }
  const std::vector<Neighbour>& neighbours() const { return neighbours_; }
  /// The other robots' true bodies, which the onboard lidar sees.
  void set_true_neighbours(std::vector<geometry::Polygon> footprints) { true_neighbours_ = std::move(footprints); }
  /// A lidar scan measured from where the robot really is (`truth`) of the other robots' bodies
  /// and the enabled static obstacles, filed under where it believes it is (`estimate`): its
  /// localization error shows in what it maps, as it would on real hardware.
  planning::LidarScan scan(const geometry::Pose2& truth, const geometry::Pose2& estimate) const;

  // --- the route and the stop -----------------------------------------------------------------
  TrafficFollower& follower() { return follower_; }
  const TrafficFollower& follower() const { return follower_; }
  SafetyStop& safety() { return safety_; }
  const SafetyStop& safety() const { return safety_; }

 private:
  void reset_obstacles();
  /// The static grid to the planners, when an obstacle changed it since they last had it.
  void hand_grid_to_planners();
  /// both_ways_ for the site and route graph now.
  void make_both_ways();

  NavigationParams params_;
  std::shared_ptr<const map::SiteMap> site_;
  planning::StaticGrid static_grid_;
  std::map<std::string, bool> obstacles_;
  planning::RoadPlanner road_;
  planning::GridAStar grid_astar_;
  planning::RoutePlanner routes_;
  /// The site's graph in both directions, when both_ways_when_closed applies.
  struct BothWays {
    BothWays(const map::RoadGraph& graph, planning::GridAStar& grid, const planning::RoutePlannerConfiguration& c)
        : road(graph), routes(road, grid, c) {}
    planning::RoadPlanner road;
    planning::RoutePlanner routes;
  };
  std::unique_ptr<BothWays> both_ways_;
  std::uint64_t grid_revision_;
  planning::LidarSim lidar_;
  std::vector<Neighbour> neighbours_;
  std::vector<geometry::Polygon> true_neighbours_;
  TrafficFollower follower_;
  SafetyStop safety_;
};

}  // namespace fleet::robot
