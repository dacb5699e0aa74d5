#pragma once

#include <cstdint>
#include <deque>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"
#include "map/road_graph.hpp"
#include "map/site_map.hpp"
#include "traffic/traffic_manager.hpp"

namespace fleet::traffic {

/// A discrete-time multi-robot simulation on the road graph, for tests and evaluation: point
/// robots drive their routes at constant speed, only as far as the manager grants (or ignoring
/// grants, the uncoordinated baseline), and the run counts trips, waits, footprint collisions and
/// deadlocks. Deterministic for a given seed.
struct SimParams {
  double speed = 0.2;              ///< m/s along the route
  double dt = 0.05;                ///< s per step; the manager updates every step
  double dwell = 2.0;              ///< s standing at a pick or drop
  double deadlock_timeout = 60.0;  ///< s without progress on a task that count as a deadlock
  geometry::Footprint footprint;   ///< for the collision count (no margin) when robot_types is empty
  /// Vehicle type of robot i + 1 (index into the configuration's vehicle types); robots beyond
  /// the list are type 0. Given: each robot plans on its type's graph, and collisions are counted
  /// between the types' footprints.
  std::vector<int> robot_types;
  bool traffic = true;          ///< false: drive the whole route regardless of others
  bool random_trips = true;     ///< robots without goals get a random pick and drop
  bool check_invariant = true;  ///< verify the manager's safety invariant every step
  std::uint64_t seed = 1;
};

struct SimReport {
  double sim_seconds = 0.0;
  int robots = 0;
  std::size_t goals_reached = 0;
  std::size_t trips = 0;        ///< pick then drop completed
  double mean_trip_s = 0.0;     ///< from being given a pick to leaving the drop
  std::size_t collisions = 0;   ///< pairs of footprints that start to overlap
  std::size_t deadlocks = 0;    ///< robots with a task not moving for deadlock_timeout
  std::vector<int> stalled_at;  ///< per deadlock: the route point the robot stood nearest
  double max_wait_s = 0.0;      ///< longest continuous wait the manager reported
  std::size_t invariant_violations = 0;
  std::string first_violation;
  std::size_t reroutes = 0;  ///< bounded-wait and deadlock re-routes
  std::size_t sidings = 0;
  std::size_t unresolved_cycles = 0;  ///< update cycles in which a wait-for cycle had no way out
  std::string first_collision;        ///< time, robots and positions of the first collision
  /// Per deadlock, who stalled where and what it waited for (the manager's last grant), to read a
  /// jam back without a debugger (`fleetctl traffic-eval --verbose`).
  std::vector<std::string> stall_notes;
};

/// Where robots work and start on a site.
struct SimScenario {
  std::vector<int> goal_points;   ///< graph points in front of the loading areas
  std::vector<int> start_points;  ///< one per robot, pairwise non-conflicting
};

/// Goals: the graph point nearest each loading area's approach position (`approach_distance` in
/// front of the pallet). Starts: for each robot the graph point nearest a home (cycling through
/// the homes, then the goal points) that conflicts with no start chosen before, for the two
/// robots' vehicle types (`robot_types[i]` for robot i, type 0 beyond the list).
SimScenario site_scenario(const map::SiteMap& site, const ConflictZones& zones, int robots,
                          double approach_distance = 0.30, const std::vector<int>& robot_types = {});

class TrafficSim {
 public:
  /// Robot i has id i + 1 and starts at start_points[i].
  TrafficSim(const map::RoadGraph& graph, const TrafficConfiguration& configuration, const SimParams& params,
             const std::vector<int>& goal_points, const std::vector<int>& start_points);

  /// Appends a goal for a robot (scripted runs: set random_trips = false).
  void add_goal(int robot_id, int point);
  /// The robot vanishes (lost): the manager frees what it held.
  void remove_robot(int robot_id);
  void step();
  /// Steps until `seconds` of simulated time have passed since the start; returns the report.
  const SimReport& run_until(double seconds);

  double time() const { return time_; }
  const SimReport& report() const { return report_; }
  TrafficManager& manager() { return manager_; }
  /// What the manager answered in the last step.
  const UpdateResult& last_update() const { return last_update_; }
  geometry::Pose2 pose(int robot_id) const;
  /// True when the robot has no goals left and stands at the end of its route.
  bool idle(int robot_id) const;
  std::size_t goals_reached(int robot_id) const;

 private:
  struct Body {
    int id = 0;
    bool active = true;
    std::vector<int> route;
    std::vector<double> cum;
    std::uint64_t version = 0;
    double distance = 0.0;
    double granted = 0.0;
    std::size_t segment = 0;
    geometry::Pose2 pose;
    std::deque<int> goals;
    int goal = -1;  ///< point the current route is meant to reach, -1 when none
    bool carrying = false;
    double dwell_until = -1.0;
    double trip_start = -1.0;
    double total = 0.0;
    double last_progress = 0.0;
    bool deadlocked = false;
    std::size_t reached = 0;
  };

  void set_route(Body& body, std::vector<int> route, std::uint64_t version);
  void start_next_goal(Body& body);
  void advance(Body& body);
  void check_collisions();
  std::string describe(const Body& body) const;
  std::string stall_note(const Body& body) const;
  Body* find(int robot_id);
  const Body* find(int robot_id) const;

  map::RoadGraph graph_;
  SimParams params_;
  TrafficManager manager_;
  RouteSearch search_;                                     ///< edge lengths
  std::vector<std::unique_ptr<RouteSearch>> type_search_;  ///< trips, on each type's route graph
  int type_of(int robot_id) const;
  std::vector<int> goal_points_;
  std::vector<Body> bodies_;
  std::vector<std::uint8_t> overlapping_;  ///< pairs overlapping in the previous step
  std::mt19937_64 rng_;
  double time_ = 0.0;
  double trip_time_sum_ = 0.0;
  SimReport report_;
  UpdateResult last_update_;
};

}  // namespace fleet::traffic
