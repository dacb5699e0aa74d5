#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <unordered_map>
#include <vector>

#include "coordination/place_graph.hpp"

namespace fleet::coordination {

/// A robot on a road site as the planner sees it.
struct PlaceRobot {
  int type = 0;
  int place = 0;       ///< -1: not on the roads (not planned, planned -1)
  int goal = -1;       ///< -1: no errand, the robot only keeps out of the way
  bool held = false;   ///< working at a place (a pick, a drop) or stopped: planned to stay, never pushed
  int preferred = -1;  ///< the next place of the route it drives: first among equally near candidates
  /// Off the roads (place -1): the place it waits to enter them at, -1 when none. Robots standing
  /// in its way (at places conflicting with it, or in its way out, ClosedPlaces::by_area) are
  /// pushed out of it before anyone else is planned.
  int entering = -1;
  /// Off the roads: robots standing in its area (ClosedPlaces::by_area of it: its way onto the
  /// roads, a manoeuvre it waits to begin) are pushed out of it, as for `entering`.
  bool pushes_from_area = false;
};

inline constexpr int kOpen = -1;          ///< ClosedPlaces: no robot closes the place
inline constexpr int kClosedByMany = -2;  ///< ClosedPlaces: several robots close it

/// Places robots may not plan into, by vehicle type and place, each entry naming the robot that
/// closes it (kOpen, kClosedByMany): a robot's own body or area never closes a place to itself.
struct ClosedPlaces {
  /// Where bodies standing beside the roads (or waiting to enter them), which the planner does
  /// not move, reach.
  std::vector<std::vector<int>> by_body;
  /// Where the area a robot sweeps driving out onto the roads reaches: closed to robots outside
  /// it, and passable for those already in it, so that they can drive out of it.
  std::vector<std::vector<int>> by_area;

  /// Of places bodies close: per vehicle type and move into them (from a neighbour), the robot
  /// whose body reaches what that move sweeps (traffic::ConflictZones::body_reaches_move), kOpen
  /// when none does. A body may close a place to the ways that turn through it and leave it open
  /// to those that drive straight through.
  std::vector<std::unordered_map<std::uint64_t, int>> by_move;

  ClosedPlaces() = default;
  ClosedPlaces(std::size_t types, std::size_t places)
      : by_body(types, std::vector<int>(places, kOpen)),
        by_area(types, std::vector<int>(places, kOpen)),
        by_move(types) {}
  static std::uint64_t move_key(int from, int to) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32) | static_cast<std::uint32_t>(to);
  }
  /// The robot closing `place` to `robot` (of `type`, standing at `from`, -1 off the roads), kOpen
  /// when none does.
  int closer(int type, int place, int robot, int from) const {
    const auto t = static_cast<std::size_t>(type);
    int body = by_body[t][static_cast<std::size_t>(place)];
    if (body != kOpen && body != robot && from >= 0 && from != place && t < by_move.size()) {
      if (const auto move = by_move[t].find(move_key(from, place)); move != by_move[t].end()) body = move->second;
    }
    if (body != kOpen && body != robot) return body;
    const int area = by_area[t][static_cast<std::size_t>(place)];
    const bool inside = from >= 0 && by_area[t][static_cast<std::size_t>(from)] == area;
    return area != kOpen && area != robot && !inside ? area : kOpen;
  }
};

/// Priority inheritance with backtracking [Okumura 2022, Algorithm 1] on places that conflict
/// with their neighbours: a robot's body covers more than its place, so a place is free for a
/// robot only when no other robot stands or is planned at a place conflicting with it for their
/// two vehicle types (traffic::ConflictZones). Every robot's next place is planned together, one
/// move at a time; the robot that has waited longest since its last goal goes first, robots
/// held at a place before all. A robot's candidates are its place and its type's successors,
/// nearest its goal first. A robot that wants a place conflicting with where others stand lends
/// each of them its priority: each moves out of the way or, as a body spans several places and
/// one move may not clear it, one move along a shortest way out of it (forward or backing up
/// against its lane's direction, never through where the pusher's body is), the pusher pushing
/// again each step. When the way is not clear, the pusher tries its next candidate. A robot
/// whose way is blocked by one that must pass where it stands and cannot be pushed clear (in a
/// spur, or boxed in) backs off for it instead, the other following [Okumura 2023, section 5].
///
/// What a plan step guarantees, for every two robots i and j moving from p to q (p = q when
/// standing):
/// - q_i and q_j do not conflict, nor do p_i and p_j (where they stand);
/// - when q_i conflicts with p_j, j moves (i follows j) and j does not follow i, directly or along
///   a chain: the robots one follows form no cycle. A robot that pushes others is "in progress"
///   until they have moved, and no robot may plan into a place conflicting with an in-progress
///   robot's place; every other follow goes to a robot already planned to move, so the follow
///   relation is built in planning order and cannot close a cycle.
/// Robots moving a step together pass the midpoints of their moves at once; before it each body
/// is inside its p's region, after it inside its q's, so no two bodies overlap (the regions are
/// the zones'). coordination::PlaceSim moves its robots in lock-step so.
class PlacePibt {
 public:
  PlacePibt(PlaceGraph& graph, std::uint64_t seed);

  /// Every robot's place after one move: its own or one of its type's successors (-1 for a robot
  /// not on the roads). The robots' places must not conflict with one another.
  std::vector<int> plan(const std::vector<PlaceRobot>& robots, const ClosedPlaces* closed = nullptr);
  /// Tells the planner that a robot reached its goal: its priority starts over.
  void reached_goal(int robot);

 private:
  enum class Check { kFree, kTaken, kBlocked };
  /// Plans one robot; `pusher` (-1 when none) wants place `wanted`, which conflicts with where it stands.
  void plan_robot(int robot, int pusher, int wanted);
  /// Whether robot may plan into place: kTaken when a planned or in-progress robot rules it out,
  /// kBlocked when unplanned robots stand in the way (then listed in `blockers`).
  Check check(int robot, int place, std::vector<int>& blockers) const;
  double candidate_cost(int robot, int place) const;
  /// The robot's move nearest its goal, -1 when staying is as near (or it has no goal).
  int best_move(int robot) const;
  /// A robot that stays backs off for one in its way that must pass where it stands; whether it does.
  bool give_way(int robot);
  /// Robot takes one move off the way of `other`, which wants to pass where it stands, and other
  /// follows it; whether it could.
  bool back_off(int robot, int other);
  /// Raises the robot's priority above every other's from the next plan on (a robot another
  /// backs off for, until it reaches its goal).
  void lend_top_priority(int robot);
  /// The robot's next places from `from` on, each its nearest to its goal.
  std::vector<int> path_ahead(int robot, int from) const;
  /// Whether robot's move to `place` meets another robot head-on where their ways share the road
  /// (a single-lane stretch, a bend where a long body swings over the other lane): the move puts
  /// it in the other's way ahead while the other stands (or is planned) in its own, and it was not
  /// in the other's way before. The first in keeps the stretch; the other waits outside it. Only
  /// where one of the two cannot back up: two that can sort a meeting out by backing off.
  bool meets_head_on(int robot, int place) const;
  /// The first of robot's moves on a shortest way to a place clear of `path` (other's), not
  /// through other's body nor (around_standing) through robots standing; -1 when none is near.
  int first_move_off(int robot, int other, const std::vector<int>& path, bool around_standing);
  void take(int robot, int place);
  /// Robot wants `place`: each of the unplanned robots `standing` in its way is pushed (planned
  /// with robot as its pusher) [Okumura 2022, Algorithm 1].
  void push_out_of_the_way(int robot, int place, const std::vector<int>& standing);
  /// Whether a robot of `type` at `place` is in the way of `pusher`, which wants place `wanted`
  /// (conflicting with it; -1: none) or, off the roads, to enter them there or to sweep its area
  /// (ClosedPlaces::by_area).
  bool in_way_of(int type, int place, int pusher, int wanted) const;
  /// Moves robot needs from `from` to a place clear of `wanted`, which `pusher` wants, without
  /// passing where the pusher's body is or a planned robot rules out; kFar when none is near.
  int moves_out(int robot, int from, int pusher, int wanted);
  static constexpr int kFar = 1 << 20;
  struct WayOut {
    int moves = kFar;  ///< moves from the start to the place found, kFar when none
    int first = -1;    ///< the first of them, -1 when none or the start itself was accepted
  };
  /// The shortest way of robot's moves from `from` to a place `clear(place)` accepts, within
  /// `reach` moves, never through `other`'s body (moves_out and first_move_off).
  template <typename Clear>
  WayOut search_way(int robot, int from, int other, int reach, bool around_standing, const Clear& clear);

  /// Plans a robot with an errand stays put before it backs off for a robot that must pass it:
  /// pushing sorts most meetings out, and backing off too early turns crowds into shuffles.
  static constexpr int kStandingBeforeSwap = 4;
  /// Plans a robot with an errand stays put before it backs up, where that is free, rather than stand.
  static constexpr int kStandingBeforeBackingUp = 12;

  /// Whether robots of the type back up (traffic::VehicleType::backs_up; true without types).
  bool backs_up(int type) const;
  /// The places the robot backs up to from `place` along its lane: none for a type that does
  /// not back up (traffic::VehicleType::backs_up).
  const std::vector<int>& moves_back(int type, int place) const;

  PlaceGraph& graph_;
  std::vector<std::uint8_t> backs_up_;  ///< by vehicle type
  std::mt19937_64 rng_;
  std::vector<double> priority_;
  std::vector<int> last_place_;         ///< per robot: its place at the last plan
  std::vector<int> standing_plans_;     ///< per robot: plans in a row it stayed at its place with an errand
  std::vector<int> giving_way_to_;      ///< per robot: the robot it backed off for at the last plan, -1
  std::vector<int> forward_only_;       ///< the robots on the roads whose type does not back up
  std::vector<std::vector<int>> ways_;  ///< per robot: its places ahead at this plan (path_ahead), none when held
  std::vector<PlaceRobot> robots_;      ///< the state being planned from
  const ClosedPlaces* closed_ = nullptr;
  std::vector<int> standing_;      ///< per place: the robot standing there, -1
  std::vector<int> planned_at_;    ///< per place: the robot planned there, -1
  std::vector<int> planned_;       ///< per robot: its next place, -1 while not planned
  std::vector<int> search_depth_;  ///< per place: moves from the search's start, kFar when not reached
  std::vector<int> search_touched_;
  std::vector<int> search_first_;      ///< per place: the first move of the way found to it
  std::vector<std::uint8_t> pushing_;  ///< per robot: in progress, waiting for the robots it pushes
};

/// Which rule of a plan step (PlacePibt's class comment) a step from `robots` to `next` breaks,
/// naming the robot by its index, or "" when it keeps them all: a held robot stays, no two robots
/// stand or are planned at conflicting places, no robot is planned into a place conflicting with
/// one that stays, and the robots that follow one another form no cycle.
std::string broken_step_rule(const traffic::ConflictZones& zones, const std::vector<PlaceRobot>& robots,
                             const std::vector<int>& next);

}  // namespace fleet::coordination
