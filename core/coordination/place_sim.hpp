#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "coordination/place_pibt.hpp"
#include "coordination/visit_order.hpp"
#include "geometry/pose.hpp"
#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

struct PlaceSimParams {
  double speed = 0.2;              ///< m/s, how fast every robot drives a move
  double dt = 0.05;                ///< s per simulation step
  double dwell = 2.0;              ///< s standing at a pick or drop
  double deadlock_timeout = 60.0;  ///< s without a move while having a goal that count as a deadlock
  /// Moves a robot's plan may run ahead of where it is: a robot this far behind is held in the plan
  /// (planned to stay, never pushed) until it catches up.
  int plan_ahead = 2;
  std::vector<int> robot_types;  ///< vehicle type of robot i (zones' numbering); beyond the list: 0
  /// Delays: each move, with this probability, stops once at a random point along it for a time
  /// drawn between delay_min_s and delay_max_s, whatever the plan (a robot stopped by a person, a
  /// slow turn, a lost network packet).
  double delay_probability = 0.0;
  double delay_min_s = 0.0;
  double delay_max_s = 0.0;
  std::uint64_t seed = 1;
};

struct PlaceSimReport {
  double sim_seconds = 0.0;
  int robots = 0;
  std::size_t plan_steps = 0;
  std::size_t moves = 0;  ///< moves driven to their end
  std::size_t goals_reached = 0;
  std::size_t trips = 0;           ///< pick then drop completed
  double mean_trip_s = 0.0;        ///< from being given a pick to leaving the drop
  std::size_t collisions = 0;      ///< pairs of footprints that start to overlap
  std::size_t deadlocks = 0;       ///< robots with a goal that stood deadlock_timeout without a move
  double max_wait_s = 0.0;         ///< longest any robot with a goal stood without a move
  std::size_t plan_conflicts = 0;  ///< plan steps breaking a rule of PlacePibt (there should be none)
  std::size_t wait_cycles = 0;     ///< simulation steps in which robots waited in a cycle (none)
  std::size_t delays = 0;          ///< moves that stopped on the way
  double planning_ms_max = 0.0;
  double planning_ms_mean = 0.0;
  std::string first_collision;
  std::string first_plan_conflict;
  std::string first_wait_cycle;
  /// Per deadlock, the robot and those standing near it (`fleetctl traffic-eval --verbose`).
  std::vector<std::string> stall_notes;
};

/// A multi-robot simulation on a road site: PlacePibt plans every robot's next place in plan steps
/// (one step about as long as a typical move), and each robot drives its planned moves at its own
/// pace, through the order the plan gives its visits of places. Up to the midpoint of a move a
/// robot's body is inside the region of the place it leaves, past it inside the region of the
/// place it goes to; it passes the midpoint into a place only once every visit of a place
/// conflicting with it that the plan begins earlier has ended. The visits so ordered form an
/// action dependency graph, acyclic as every dependency points to an earlier plan step, or, within
/// one step, along the robots' follow relation, which PlacePibt keeps acyclic: however late any
/// robot runs, some robot can always move and no two bodies meet [Hönig 2019, section IV]. Moves
/// may stop on the way at random (the delay parameters); a robot whose plan runs `plan_ahead`
/// moves ahead of it is held in the plan until it catches up.
///
/// Robots take random trips between goal points (pick, dwell, drop, dwell), as traffic::TrafficSim
/// does, so the two coordinations compare trip for trip. Footprints are checked for overlap every
/// simulation step. A load generator of kinematic robots, not the agents. Deterministic for a
/// given seed.
class PlaceSim {
 public:
  /// Robot i starts at start_points[i]; goal and start points are road graph point ids.
  PlaceSim(const map::RoadGraph& graph, const traffic::ConflictZones& zones, const PlaceSimParams& params,
           const std::vector<int>& goal_points, const std::vector<int>& start_points);

  void step();
  const PlaceSimReport& run_until(double seconds);
  const PlaceSimReport& report() const { return report_; }
  double time() const { return time_; }
  /// The place robot i's body is in: where it stands, or the place it moves to once past the
  /// move's midpoint.
  int place(int robot) const { return order_.place(robot); }

 private:
  struct Body {
    int type = 0;
    double progress = 0.0;  ///< metres along the move from its current visit's place to its next's
    double length = 0.0;
    double pause_at = -1.0;  ///< metres along the move where a delay stops it, -1: none
    double pause_s = 0.0;
    double yaw = 0.0;
    int goal = -1;  ///< goal place, -1 while dwelling
    bool carrying = false;
    double dwell_until = 0.0;
    double trip_start = 0.0;
    double still_since = 0.0;
    bool deadlocked = false;
  };

  void start_next_goal(std::size_t robot);
  void plan_step();
  void begin_move(std::size_t robot);
  void drive(std::size_t robot);
  void note_wait_cycle();
  std::string stall_note(std::size_t robot) const;
  void check_collisions();
  geometry::Pose2 pose_of(std::size_t robot) const;
  void arrive(std::size_t robot);
  void note_stall(std::size_t robot);

  const traffic::ConflictZones& zones_;
  PlaceGraph graph_;
  PlacePibt planner_;
  VisitOrder order_;
  PlaceSimParams params_;
  std::vector<int> goal_places_;
  std::vector<Body> bodies_;
  std::vector<std::uint8_t> overlapping_;
  double reach_ = 0.0;          ///< no two bodies farther apart than this can touch
  double plan_period_s_ = 0.5;  ///< a plan step: the typical move's time
  double next_plan_ = 0.0;
  std::size_t plan_step_ = 0;
  std::mt19937_64 rng_;
  double time_ = 0.0;
  double trip_time_sum_ = 0.0;
  double planning_ms_sum_ = 0.0;
  PlaceSimReport report_;
};

}  // namespace fleet::coordination
