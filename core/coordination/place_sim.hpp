#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "coordination/place_pibt.hpp"
#include "geometry/pose.hpp"
#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

struct PlaceSimParams {
  double speed = 0.2;              ///< m/s, the fastest any robot drives a move
  double dwell = 2.0;              ///< s standing at a pick or drop
  double deadlock_timeout = 60.0;  ///< s without a move while having a goal that count as a deadlock
  std::vector<int> robot_types;    ///< vehicle type of robot i (zones' numbering); beyond the list: 0
  std::uint64_t seed = 1;
};

struct PlaceSimReport {
  double sim_seconds = 0.0;
  int robots = 0;
  std::size_t moves = 0;  ///< plan steps in which some robot moved
  std::size_t goals_reached = 0;
  std::size_t trips = 0;           ///< pick then drop completed
  double mean_trip_s = 0.0;        ///< from being given a pick to leaving the drop
  std::size_t collisions = 0;      ///< pairs of footprints that start to overlap
  std::size_t deadlocks = 0;       ///< robots with a goal that stood deadlock_timeout without a move
  double max_wait_s = 0.0;         ///< longest any robot with a goal stood without a move
  std::size_t plan_conflicts = 0;  ///< plan steps breaking a rule of PlacePibt (there should be none)
  double planning_ms_max = 0.0;
  double planning_ms_mean = 0.0;
  std::string first_collision;
  std::string first_plan_conflict;
  /// Per deadlock, the robot and those standing near it (`fleetctl traffic-eval --verbose`).
  std::vector<std::string> stall_notes;
};

/// A multi-robot simulation in plan steps on a road site, coordinated by PlacePibt: each step the
/// planner gives every robot its next place, and the robots drive there together, the step lasting
/// as long as the longest move takes at `speed`. Robots take random trips between goal points
/// (pick, dwell, drop, dwell), as traffic::TrafficSim does, so the two coordinations compare trip
/// for trip. Footprints are checked for overlap a quarter of a move at a time. A load generator of
/// kinematic robots, not the agents. Deterministic for a given seed.
class PlaceSim {
 public:
  /// Robot i starts at start_points[i]; goal and start points are road graph point ids.
  PlaceSim(const map::RoadGraph& graph, const traffic::ConflictZones& zones, const PlaceSimParams& params,
           const std::vector<int>& goal_points, const std::vector<int>& start_points);

  void step();
  const PlaceSimReport& run_until(double seconds);
  const PlaceSimReport& report() const { return report_; }
  double time() const { return time_; }
  /// Where robot i stands (a place of the zones).
  int place(int robot) const { return bodies_[static_cast<std::size_t>(robot)].place; }

 private:
  struct Body {
    int type = 0;
    int place = 0;
    double yaw = 0.0;
    int goal = -1;  ///< goal place, -1 while dwelling
    bool carrying = false;
    double dwell_until = 0.0;
    double trip_start = 0.0;
    double still_since = 0.0;
    bool deadlocked = false;
  };

  void start_next_goal(Body& body);
  std::string stall_note(std::size_t robot) const;
  void check_plan(const std::vector<PlaceRobot>& robots, const std::vector<int>& next);
  void check_collisions(const std::vector<int>& next, double dt);
  geometry::Pose2 pose_at(const Body& body, int next, double fraction) const;
  void arrive(std::size_t robot, int next);

  const traffic::ConflictZones& zones_;
  PlaceGraph graph_;
  PlacePibt planner_;
  PlaceSimParams params_;
  std::vector<int> goal_places_;
  std::vector<Body> bodies_;
  std::vector<std::uint8_t> overlapping_;
  std::mt19937_64 rng_;
  double time_ = 0.0;
  double idle_step_s_ = 0.5;  ///< a step in which no robot moves: the typical move's time
  double trip_time_sum_ = 0.0;
  double planning_ms_sum_ = 0.0;
  std::size_t plans_ = 0;
  PlaceSimReport report_;
};

}  // namespace fleet::coordination
