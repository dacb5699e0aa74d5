#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"
#include "traffic/one_way.hpp"
#include "traffic/route_search.hpp"
#include "traffic/vehicle_lanes.hpp"

namespace fleet::traffic {

/// Fixed per TrafficManager: the zones are precomputed from it.
struct TrafficConfiguration {
  ResourceParams resources;
  double lookahead = 0.6;        ///< metres of route granted ahead of a robot when the road is free
  double release_margin = 0.02;  ///< metres past an edge's midpoint before the place behind is freed
  double stop_tolerance = 0.02;  ///< a robot this close to the end of its grant counts as stopped there
  /// Seconds a stopped robot waits before its next stretch is reserved for it: younger robots may
  /// then not enter it (unless they are what it waits for). This is what makes waiting fair.
  double priority_wait = 8.0;
  /// Seconds: the bound on waiting. A robot waiting this long is re-routed around its blockers
  /// (when a route exists), at most once per bound.
  double reroute_wait = 30.0;
  /// Seconds a robot waits on robots that are all lost before it is re-routed around them: a
  /// lost robot holds where it stands for as long as it is away (a frozen process, a restart),
  /// so waiting out the whole bound behind it only adds to the fault.
  double lost_reroute_wait = 3.0;
  double yield_timeout = 20.0;  ///< seconds a robot sent to a siding stays there at most
  /// Metres of the other robots' routes (ahead of them) a siding must keep clear of, and of the
  /// yielding robot's way back that must be clear of them before it resumes.
  double siding_window = 3.0;
  /// Vehicle type of each robot by name (its fleet's, configuration_from); robots not listed are
  /// type 0. The manager knows robots by number: the server tells it (set_robot_type).
  std::map<std::string, int> robot_vehicle_types;
  /// Give corridors between junctions one driving direction (see OneWayPlan) and plan re-routes
  /// on that graph; robots should then plan on `route_graph()` too. Off: every road both ways.
  bool one_way = true;
};

/// A robot's route: graph point ids from where it stands to its goal, consecutive points joined
/// by graph edges. `version` must grow with every new route of the robot.
struct RouteRequest {
  int robot_id = 0;
  std::uint64_t version = 0;
  std::vector<int> points;
};

/// How far a robot has driven along its route version, metres from the route's first point.
struct ProgressReport {
  int robot_id = 0;
  std::uint64_t version = 0;
  double distance = 0.0;
  /// Robots whose bodies the robot's own safety check has kept it standing for (the agents'
  /// check is finer than the places: bodies turning onto a road or cutting a corner reach past
  /// them). The manager counts it as waiting for them, so a robot it waits for in turn closes a
  /// cycle that resolve_cycles breaks.
  std::vector<int> stopped_for;
};

enum class SubmitStatus {
  kAccepted,
  kStale,    ///< version not newer than the manager's (e.g. the manager re-routed the robot)
  kInvalid,  ///< empty, unknown points, points not joined by edges, or not starting where the robot is
};

enum class GrantStatus {
  kMoving,   ///< granted beyond where the robot is
  kWaiting,  ///< stopped at the end of its grant, the road ahead held by others
  kArrived,  ///< at the end of its route
};

enum class Instruction {
  kNone,
  kReroute,  ///< drive `route` instead (a way round, or back from a siding to the goal)
  kSiding,   ///< drive `route` to a siding and wait there; the manager sends the way back later
};

/// What the server sends a robot each cycle: "drive route version `version` up to point index
/// `granted_index` (metres `granted_distance`) and stop there".
struct Grant {
  int robot_id = 0;
  std::uint64_t version = 0;
  int granted_index = 0;
  double granted_distance = 0.0;
  GrantStatus status = GrantStatus::kMoving;
  double waited_s = 0.0;  ///< how long the robot has been waiting, 0 when not waiting
  /// Robot ids holding the road beyond the grant, and entrants whose claim keeps it out (it will
  /// wait for them).
  std::vector<int> blocked_by;
  /// kReroute / kSiding: `route` (version `version`) replaces the robot's route. Repeated in every
  /// grant until the robot reports progress on that version.
  Instruction instruction = Instruction::kNone;
  std::vector<int> route;
};

struct TrafficEvent {
  enum class Kind {
    kDeadlockResolved,
    kRerouted,
    kSidingSent,
    kResumed,
    kRobotRemoved,
    kUnresolvedDeadlock,
    kGaveWay,  ///< a robot stopped by the bodies of `others` gave back the road it held beyond itself
  };
  Kind kind = Kind::kRerouted;
  double time = 0.0;
  int robot_id = 0;
  std::vector<int> others;  ///< the robots it yields to, or the cycle's members
};

struct UpdateResult {
  std::vector<Grant> grants;  ///< one per robot, by robot id
  std::vector<TrafficEvent> events;
};

/// Reservation-based traffic control on a road graph, for a single-threaded server loop.
///
/// Each cycle the server feeds the manager new routes (`submit_route`), progress reports
/// (`report_progress`) and lost robots (`remove_robot`), then calls `update(now)` and sends every
/// robot its Grant. Robots drive only up to the end of their grant and report progress.
///
/// **Resources and safety.** Resources are the places of ConflictZones. A robot holds the places
/// of its route from the one it is leaving to the end of its grant; a place is freed once the
/// robot has driven past the midpoint of the edge beyond it (plus `release_margin`), so release
/// follows distance travelled, not node arrivals. Invariant: no place one robot holds conflicts
/// with a place another holds. Grants only add places that conflict with nothing another robot
/// holds, and places are only freed behind a robot (or all at once when it is removed), so the
/// invariant holds by construction; `check_invariant` verifies it in tests.
///
/// **Grants.** In priority order (longest waiting first, then robot id) each robot's grant grows
/// towards `lookahead` metres ahead, in stretches that end only at *stoppable* places (outside
/// every junction zone) or at the route's end, so a waiting robot never stands in a junction.
///
/// **Avoiding deadlock.** Cycles of waiting robots are made rare by construction:
/// 1. One-way corridors (`one_way`, default on): every corridor that lies on a cycle of the road
///    network gets one direction, keeping every place reachable (OneWayPlan). Robots planning on
///    `route_graph()` never meet head-on there; the remaining two-way corridors are dead ends,
///    bridges and junction interiors.
/// 2. Corridor direction: a robot may not drive into a corridor towards another robot that drives
///    the other way in it, or that stands at the end of its route in a two-way corridor (it may
///    leave either way; in a one-way corridor it leaves ahead, and robots behind queue up to it).
///    Head-on meetings inside a two-way corridor therefore do not start: the second robot waits
///    outside the junction at the corridor's end.
/// 3. Fair waiting: a robot stopped longer than `priority_wait` reserves its next stretch (its
///    places and its corridor direction) against robots of lower priority that would newly enter
///    it; robots already inside, and the robots it waits for, stay free to move away. Priority is
///    the time waiting began, so every waiting robot eventually becomes the oldest: no
///    starvation (openTCS documents that its scheduler does not guarantee this).
/// 4. Bounded waiting: a robot waiting `reroute_wait` seconds is re-routed around the places held
///    by the robots it waits for, when such a route exists and can start at once.
///
/// **Detecting and breaking cycles.** The wait-for graph has an edge r -> s when stopped robot
/// r's next stretch is blocked by s's places, driving direction or reservation. Its strongly
/// connected components are found every cycle (Tarjan). A cycle of stopped robots cannot clear by
/// itself (places only free when robots move), so it is broken at once: the member of lowest
/// priority (latest to start waiting, then highest id) that has a way out gets it — a route to
/// its goal that avoids what the robots it waits for hold, or else a *siding*: the nearest
/// stoppable place it can reach without crossing anyone's places, off the remaining routes of the
/// robots waiting for it (or, failing that, off their next `siding_window` metres). The others then
/// proceed; the yielding robot is sent back to its goal once its way back is clear of them (or
/// after `yield_timeout`). A head-on meeting on a single-lane corridor resolves this way: one robot
/// backs off into a branch and lets the other pass. Failing both, a member is re-routed against
/// the one-way plan (robots placed where the plan does not expect them, e.g. by a map switch,
/// may have no other way). When no member has a way out the cycle is reported
/// (kUnresolvedDeadlock) and retried every cycle as the robots around it move.
///
/// Robots that finish a route keep holding the place they stand on (they are still there); the
/// server calls `hold_body` when a robot leaves the roads (working at a loading area its body
/// still reaches the lane; parked clear of the roads it holds nothing) and `freeze_robot` when it
/// is lost: its body still blocks where it stood. A body on a road holds the one place whose
/// region holds it whole, else every place it touches. Places held for a body may conflict with
/// another robot's (robots may stand closer than the zones' margins, e.g. when the manager starts
/// among them): grants of others into them are then pulled back to before the first such place
/// not yet reached, and grants never add such a conflict, so it only clears.
///
/// **Vehicle types.** Every robot is of one of the zones' vehicle types (`set_robot_type`, type 0
/// until told). Wherever the manager checks a place against another robot's — grants, occupancy,
/// standing bodies, entry claims, reservations, sidings — it uses the conflicts of that pair of
/// types, so a small robot may pass where a big one may not. A robot is routed and re-routed only
/// on its type's lanes (`route_graph(type)`: the lanes its footprint fits, lane_graph_for). On the
/// two lanes of one road, a robot does not enter the stretch of its lane in conflict with the
/// opposite lane while a robot in conflict with it drives the other way there (OppositeLane):
/// robots whose regions stay clear of each other pass, the others take the stretch in turn.
///
/// Deterministic: no clocks, no randomness; time is passed in. Not thread-safe.
class TrafficManager {
 public:
  TrafficManager(const map::RoadGraph& graph, const TrafficConfiguration& configuration = {});

  /// A new route for a robot (a new robot enters at the route's first point: check
  /// holders_in_conflict() first, entering is not checked here). The first point must
  /// be a place the robot holds; the places it held behind that point stay held until it has
  /// driven past the first edge's midpoint. A standing robot's new route pulls back others'
  /// grants into what it holds, as hold_body does.
  /// kInvalid also when the route enters a lane the robot's vehicle type does not fit.
  SubmitStatus submit_route(const RouteRequest& request, double now);
  /// The robot's vehicle type (index into zones().vehicle_types()); kept across removals, so it
  /// may be told before the robot enters. False (and nothing changes) for an unknown type.
  bool set_robot_type(int robot_id, int type);
  int robot_type(int robot_id) const;
  /// Progress on the current route version; other versions are ignored. Clamped to the grant.
  void report_progress(const ProgressReport& report, double now);
  /// Frees everything the robot holds (parked off the graph); the next update reports it.
  /// False for unknown ids.
  bool remove_robot(int robot_id, double now);
  /// The robot stopped answering (lost): its body still stands where it was last seen, so it
  /// keeps only the places under its footprint `body` (see the class comment; none when it stood
  /// beside the roads: then it is removed) and gives up the rest. It is granted nothing more
  /// until it reports progress or a new route again. False for unknown ids.
  bool freeze_robot(int robot_id, const geometry::Polygon& body, double now);
  /// A robot standing without a route — off the roads at a loading area, or not yet admitted (the
  /// manager just started after a map switch or a server restart) — holds the places under its
  /// footprint `body`, like a frozen robot, so no robot is granted into it. Unknown robots are added; a robot on a
  /// route is left alone (false). When `body` overlaps no place the robot is removed (false).
  /// A standing robot that sends a route starting at a place under it enters there at once
  /// (submit_route): it is already there.
  bool hold_body(int robot_id, const geometry::Polygon& body, double now);
  /// A robot standing beside the roads (hold_body) waits for `blockers` to leave the area it is
  /// to work in (a stacker's docking). It counts as waiting for them, so a robot that waits in
  /// turn for its body closes a cycle that resolve_cycles breaks by moving that robot; the
  /// standing robot itself is never sent anywhere. Empty: it waits no more. Dropped with the
  /// robot and when it sends a route.
  void wait_for_area(int robot_id, std::vector<int> blockers);
  /// Robots that work together at one place (a loader and the transporter behind it), by id, each
  /// pair once: neither is kept out of a place by what the other holds. The desk that pairs them
  /// orders their moves (the transporter moves up ahead of its picker), the two stand closer than
  /// any two others by design, and each one's own safety check keeps it off the other's body.
  ///
  /// Each pair is (transporter, loader). A transporter whose route ends in a one-way corridor and
  /// that holds places there closes the corridor behind it (upstream) to every robot but its
  /// partners: its loader comes to stand there, and a third robot in between would wait for the
  /// transporter, which waits for the loader behind it. A robot kept out waits before the
  /// corridor and is routed round after `lost_reroute_wait`, as behind a lost robot. A
  /// transporter whose loader is not known yet pairs with -1: its corridor closes to every robot.
  void set_partners(std::set<std::pair<int, int>> pairs) { partners_ = std::move(pairs); }
  /// The robot turns off its route's last point `goal_point` into a place beside the road (a
  /// forklift into a rack place or its home) and sweeps `area` (convex) doing so: a long body
  /// turning there swings across the lane it arrives on and into the one beside it. Its grant
  /// reaches that point only once no other robot holds a place whose region touches the area or
  /// stands in it (robots queued behind it, waiting for it, do not count: they stay put); from
  /// then on the area closes the places whose regions touch it, as a standing body does, until the
  /// robot has driven past the first edge of its next route (the way back out sweeps the same
  /// area) or leaves the roads. Asked again with every request; an empty area, or a route ending
  /// elsewhere, asks for nothing. Computing the places is a pass over every place: only when the
  /// area or the point changes.
  void set_arrival_area(int robot_id, int goal_point, const geometry::Polygon& area);
  /// A robot standing beside the roads whose body reaches onto them (a stacker docked at a pallet
  /// place) will turn out onto the lane across `area` (convex) when it leaves. Until then no other
  /// robot is granted to stop in a place whose region touches the area: it is granted through it to
  /// a place beyond, or up to before it. Robots may pass, so a docked robot whose body leaves the
  /// lanes free costs nobody anything, and robots held up by its body wait outside its way out
  /// instead of in it. Asked again with every request; an empty area asks for nothing. Dropped
  /// when the robot is removed or sends a route.
  void keep_clear(int robot_id, const geometry::Polygon& area);
  /// Whether the robot holds its arrival area (granted up to its route's last point).
  bool holds_arrival(int robot_id) const;
  /// The area of the robot's turn off the road that it still holds: its arrival area, or the one
  /// it keeps on a new route until past its first edge. Empty when none.
  geometry::Polygon turn_area(int robot_id) const;

  /// One control cycle: releases, grants, deadlock resolution. Cost grows with robots x route
  /// places x conflict-set size; no allocation proportional to the graph.
  UpdateResult update(double now);

  // ---- introspection (tests, web view) ---------------------------------------------------------
  const ConflictZones& zones() const { return *zones_; }
  /// Route search on the graph robots of `type` should plan on (`route_graph(type)`).
  RouteSearch& search(int type = 0) { return *types_[static_cast<std::size_t>(type)]->route_search; }
  /// The graph robots of `type` should plan on: the one-way graph when configured, else the input
  /// graph, with only the lanes the type fits (lane_graph_for).
  const map::RoadGraph& route_graph(int type = 0) const { return types_[static_cast<std::size_t>(type)]->route; }
  /// The input graph with only the lanes the type fits, both ways where the input drives both.
  const map::RoadGraph& lane_graph(int type) const { return types_[static_cast<std::size_t>(type)]->lanes; }
  /// Direction of each corridor under the one-way plan (+1 / -1 along corridor_index, 0 both ways).
  const std::vector<int>& corridor_directions() const { return one_way_.corridor_direction; }
  const TrafficConfiguration& configuration() const { return configuration_; }
  std::vector<int> robot_ids() const;
  bool has_robot(int robot_id) const { return robots_.count(robot_id) != 0; }
  bool frozen(int robot_id) const {
    auto it = robots_.find(robot_id);
    return it != robots_.end() && it->second.frozen;
  }
  /// Places the robot holds now, sorted.
  std::vector<int> held_places(int robot_id) const;
  /// Where a robot `progress` metres along `points` (its route) enters the roads: the last point
  /// at or behind `progress`, the points behind it cut off. A robot whose body
  /// holds places (lost and heard from again, or found standing after a restart) enters instead
  /// at the first point ahead, within its footprint's reach, whose place it holds: a robot that
  /// drove up behind it while it was away holds the place behind its centre, and waiting to enter
  /// there would be waiting for a robot that waits for its body.
  struct EntryPoint {
    std::size_t index = 0;  ///< of the point it enters at; the points before it are cut off
    double offset = 0.0;    ///< metres along `points` to that point
  };
  EntryPoint entry_point(int robot_id, const std::vector<int>& points, double progress) const;
  /// The robot holds the place of graph point `point`.
  bool holds_place_of(int robot_id, int point) const;
  /// Robots (other than `robot_id`) holding a place that conflicts with the place of graph point
  /// `point`, sorted: a robot may enter the graph there only when this is empty.
  std::vector<int> holders_in_conflict(int point, int robot_id) const;
  /// Robots (other than `robot_id`) holding a place whose region touches `area`, or whose body in
  /// `bodies` (convex, where each robot stands) overlaps it, sorted: a robot parked beside the
  /// roads holds no place, yet a manoeuvre must not sweep it. A standing robot (frozen, see
  /// hold_body) with its hold in `bodies` counts by that polygon alone: the regions of the places
  /// under it reach up to a body length beyond it, and a parked robot would keep every manoeuvre
  /// that passes it at that distance from starting. So does a robot on a route that waits for
  /// `robot_id` (with its body in `bodies`): it goes nowhere until `robot_id` has moved. A robot beside the roads
  /// starts a manoeuvre that sweeps `area` (docking in reverse, parking) only when this is empty, and then holds the
  /// area (hold_body) until the manoeuvre ends.
  std::vector<int> holders_in_area(int robot_id, const geometry::Polygon& area,
                                   const std::map<int, geometry::Polygon>& bodies = {}) const;
  /// A robot beside the roads waits to enter at `point` (see holders_in_conflict). Once it has
  /// waited `priority_wait`, the places in conflict with its entry close to robots from outside
  /// them (those inside drive on and out), so a busy road cannot keep it out for ever. The claim
  /// stays active for as long as the robots in the way take to drive off, but no longer than
  /// they can: when one of them waits, directly or down the line, on a robot the claim keeps
  /// out, the closure is lifted for `priority_wait` (the claim keeps its place in line). So
  /// nothing waits on a claim without bound, and a queue that drains slowly lets no newcomer in
  /// ahead of the entrant.
  /// Call every cycle while it waits; `drop_entry` once it entered or gave up.
  void claim_entry(int robot_id, int point, double now);
  void drop_entry(int robot_id);
  /// Robots beside the roads whose entry claim (waited `priority_wait`, lifted or not) conflicts
  /// with an entry at `point` and is older than `robot_id`'s own, sorted: first come, first in, so
  /// a robot leaving a loading area does not slip in ahead of one that has waited at its home. A
  /// claim whose entry this robot's body stands in the way of is left out (that one must go first).
  std::vector<int> earlier_entry_claims(int point, int robot_id, double now) const;
  /// How a robot beside the roads may enter at `point` now.
  struct Entry {
    std::vector<int> blockers;  ///< sorted; it waits while any is left
    /// It enters keeping what it holds (its body, the area of its way out) until it is past its
    /// route's first edge: it stands holding the entry's place, and nobody keeps it out or every
    /// robot in conflict with the entry waits for its body.
    bool as_standing = false;
  };
  /// The robots that keep `robot_id` out: holders of places in conflict with the entry
  /// (holders_in_conflict), else older entry claims (earlier_entry_claims). Holders that wait for
  /// its body do not count when its body holds the entry's place: their grants end short of it
  /// and they go nowhere until it has moved, so waiting for them would be waiting for good.
  Entry entry_for(int point, int robot_id, double now) const;
  /// The robot's current route and version (empty for unknown ids).
  const std::vector<int>& route(int robot_id) const;
  std::uint64_t version(int robot_id) const;
  /// Checks the safety invariant over all robots; returns a description of the first violation.
  std::string check_invariant() const;

 private:
  struct Robot {
    int id = 0;
    int type = 0;  ///< vehicle type
    std::uint64_t version = 0;
    std::vector<int> route;
    std::vector<int> places;
    std::vector<double> cum;         ///< metres from the route start to each point
    std::vector<double> release_at;  ///< progress past which each point's place is freed
    double progress = 0.0;
    int first_held = 0;
    int grant_end = 0;
    std::vector<int> trail;  ///< places of a previous route still held
    /// The part of `trail` granted on that route beyond where the robot stood when it was sent a
    /// new one: it may still drive into them until it reports driving the new route.
    std::vector<int> trail_ahead;
    double trail_release = 0.0;  ///< progress past which `trail` is freed
    double wait_since = -1.0;
    double last_reroute = -std::numeric_limits<double>::infinity();
    bool blocked = false;
    bool stopped = false;
    std::vector<int> blocked_by;
    std::vector<int> stopped_for;  ///< robots whose bodies its safety check stops it for (ProgressReport)
    std::vector<int> kept_out_by;  ///< entrants whose active entry claim stops its grant, sorted
    /// Robots it gave its road back to (give_way): it is granted nothing more while their bodies
    /// still stop it. Sorted.
    std::vector<int> giving_way_to;
    Instruction pending = Instruction::kNone;
    bool in_siding = false;
    int resume_goal = -1;
    std::vector<int> yield_to;
    double siding_arrival = -1.0;
    bool frozen = false;  ///< holds where it stands, granted nothing more (freeze_robot, hold_body)
    bool lost = false;    ///< frozen by freeze_robot and not heard from since
    /// While it holds where its body stands (standing, or not yet past the first edge of the
    /// route it sent from there): by vehicle type, the places whose regions of that type touch
    /// that body, sorted. A held place among its own type's closes only itself, not the places in
    /// conflict with it: another robot may drive wherever its footprint stays clear of the body
    /// (the body is not a place's whole region). Empty when it holds no body.
    std::vector<std::vector<int>> body_reach;
    geometry::Polygon body_polygon;  ///< the body (or arrival area) body_reach was found for
    bool reach_of_turn = false;      ///< body_reach is the arrival area it has yet to back out of
    /// set_arrival_area: the route end it is asked for (-1: none), the area and, by type, the
    /// places whose regions touch it, sorted; held from the grant of the route's last point.
    int arrival_point = -1;
    geometry::Polygon arrival_area;
    std::vector<std::vector<int>> arrival_reach;
    bool arrival_held = false;
  };

  void install_route(Robot& robot, std::vector<int> points, std::uint64_t version);
  /// Installs a new route for a robot on the roads; what it held before becomes its trail. A
  /// route the manager `sent` (a re-route, a siding) keeps the old grant beyond where the robot
  /// stood only until the robot reports driving the new route.
  void change_route(Robot& robot, std::vector<int> points, std::uint64_t version, bool sent);
  /// The farthest corner of a vehicle type's footprint from its reference point, metres.
  double footprint_reach(int type) const;
  /// A new route: a held arrival area stays held as the body's reach until the robot is past the
  /// new route's first edge (its way out of where it turned in); the area asked for is dropped.
  void leave_arrival(Robot& robot);
  /// The route's last point is granted next and the robot asks for an arrival area not yet held.
  bool arrival_pending(const Robot& robot, int index) const;
  /// Robots (ids, sorted) that keep the robot from turning into its arrival area now.
  std::vector<int> arrival_blockers(const Robot& robot) const;
  /// The places `robot` closes, for robots of `type`, beyond those of its route: its body's reach
  /// and its held arrival area. Calls `visit(place)` for each.
  template <typename Visit>
  void for_each_reach(const Robot& robot, int type, Visit visit) const {
    if (!robot.body_reach.empty()) {
      for (int p : robot.body_reach[static_cast<std::size_t>(type)]) visit(p);
    }
    if (robot.arrival_held) {
      for (int p : robot.arrival_reach[static_cast<std::size_t>(type)]) visit(p);
    }
  }
  /// The places a body of `type` holds (see the class comment) and, by type, the places it touches.
  std::vector<int> places_under(const geometry::Polygon& body, int type,
                                std::vector<std::vector<int>>* touched = nullptr) const;
  void stand(Robot& robot, const geometry::Polygon& body, const std::vector<int>& under,
             std::vector<std::vector<int>> touched);
  /// Whether `place` is among those the robot's body touches, in its own type's regions.
  bool under_body(const Robot& robot, int place) const { return under_body_for(robot, place, robot.type); }
  bool under_body_for(const Robot& robot, int place, int type) const;
  /// Whether `holder` keeps robots of vehicle type `type` out of `place`.
  bool closes(const Robot& holder, int place, int type) const;
  int type_of(int robot_id) const;
  /// Index of (vehicle type, place) in the typed per-place tables.
  std::size_t typed(int type, int place) const {
    return static_cast<std::size_t>(type) * zones_->place_count() + static_cast<std::size_t>(place);
  }
  /// Robots other than `robot_id` that keep others out of `place` (holders_in_conflict by place).
  std::vector<int> holders_of(int place, int robot_id) const;
  void pull_back_grants_into(const Robot& standing);
  void replace_route(Robot& robot, std::vector<int> points, Instruction instruction, double now);
  void release_passed(Robot& robot);
  int direction_at(const Robot& robot, int index) const;
  int next_stretch_end(const Robot& robot) const;
  void rebuild_occupancy();
  void mark(const Robot& robot, int slot, int index);
  bool place_free_for(int slot, const std::vector<int>& places, int index, std::vector<int>& blockers) const;
  /// The opposite-lane rule of place_free_for: robots driving towards `places[index]` in the
  /// stretch of the opposite lane in conflict with it, when the robot would enter that stretch.
  void opposite_lane_blockers(int slot, const std::vector<int>& places, int index, int direction,
                              std::vector<int>& blockers) const;
  void extend(Robot& robot, int slot);
  bool stopped_at_grant_end(const Robot& robot) const;
  /// Where a re-route or siding of the robot starts: the end of its grant when it stands there,
  /// else (stopped short of it by another robot's body) the route point at or behind it.
  int anchor_index(const Robot& robot) const;
  /// The index of the point a robot is driving into (or stands at), between its first held
  /// point and the end of its grant: the places up to it are the ones it stands in.
  int reached_index(const Robot& robot) const;
  bool reroute(Robot& robot, const std::vector<int>& others, double now, UpdateResult& out, TrafficEvent::Kind kind,
               bool against_one_way = false);
  bool give_way(Robot& robot, const std::vector<int>& members, double now, UpdateResult& out);
  /// Whether `waiter`'s next stretch beyond its grant is in conflict with the places `holder`
  /// keeps standing at route index `reached` (its trail and the places up to there).
  bool needs_places_up_to(const Robot& waiter, const Robot& holder, int reached) const;
  /// `clear_of_self`: the siding must also lie off the places in conflict with those the robot
  /// holds now, so it moves a body length at least (its body stands in another's way).
  bool send_to_siding(Robot& robot, const std::vector<int>& others, double now, UpdateResult& out,
                      bool clear_of_self = false);
  void try_resume(Robot& robot, double now, UpdateResult& out);
  void resolve_cycles(double now, UpdateResult& out);
  /// Places robots of vehicle type `type` may not enter beside `others` (by place).
  std::vector<std::uint8_t> places_of_others(const std::vector<int>& others, bool with_next_stretch, double window,
                                             int type) const;
  bool first_stretch_free(const std::vector<int>& points, int slot) const;
  /// Where the robot stands: on its route at its progress, or its body's centre beside the roads.
  geometry::Vec2 position_of(const Robot& robot) const;
  /// Places (by place) with a point nearer a robot whose body stops this one (stopped_for) than
  /// this robot stands now: ways through them lead towards a body its safety check keeps it from.
  std::vector<std::uint8_t> towards_stoppers(const Robot& robot) const;
  /// Places `robot` may not drive through on a way round or to a siding: those of the others
  /// (places_of_others, no window) and those towards its stoppers.
  std::vector<std::uint8_t> closed_to(const Robot& robot, const std::vector<int>& others, bool with_next_stretch) const;
  int slot_of(int robot_id) const;
  bool higher_priority(const Robot& a, const Robot& b) const;

  TrafficConfiguration configuration_;
  map::RoadGraph graph_;
  std::unique_ptr<ConflictZones> zones_;
  std::unique_ptr<RouteSearch> search_;  ///< on the full graph: edge lengths
  OneWayPlan one_way_;
  /// The graphs and searches of one vehicle type: only the lanes it fits.
  struct TypeGraphs {
    map::RoadGraph lanes;                       ///< the full graph: sidings may back up
    map::RoadGraph route;                       ///< route_graph(type)
    std::unique_ptr<RouteSearch> search;        ///< on `lanes`
    std::unique_ptr<RouteSearch> route_search;  ///< on `route`: re-routes and returns
  };
  std::vector<std::unique_ptr<TypeGraphs>> types_;
  std::vector<geometry::Bounds> region_bounds_;  ///< of each region's pieces, by typed(type, place)
  std::map<int, int> robot_types_;               ///< set_robot_type, by robot id
  std::map<int, Robot> robots_;                  ///< ordered by id: deterministic iteration
  std::vector<Robot*> slots_;                    ///< robots by slot (position in id order), rebuilt each update
  double now_ = 0.0;                             ///< time of the update in progress
  std::vector<TrafficEvent> removed_;            ///< removals since the last update, reported by it
  std::set<std::pair<int, int>> partners_;
  bool partnered(int a, int b) const {
    return partners_.contains({a, b}) || partners_.contains({b, a});
  }  ///< set_partners

  /// A one-way corridor closed behind a loader's transporter (set_partners): indices [lo, hi].
  struct PairClosure {
    int corridor = 0;
    int transporter = 0;  ///< slot
    int loader_id = 0;
    int lo = 0;
    int hi = 0;
  };
  std::vector<PairClosure> pair_closures_;  ///< rebuilt with the occupancy
  void close_behind_transporters();
  /// Whether a closure keeps the robot in `slot` out of `places[index]`: it enters the corridor
  /// there, inside the closed stretch, and is no partner of the pair. Adds the transporter.
  void closure_blockers(int slot, const std::vector<int>& places, int index, std::vector<int>& blockers) const;

  /// The stretch of a corridor a robot holds (or has reserved) driving one way along it.
  struct CorridorSpan {
    int slot = 0;
    int direction = 0;
    int lo = 0;  ///< lowest corridor index
    int hi = 0;  ///< highest corridor index
    bool reserved = false;
  };
  void add_span(int corridor, int slot, int direction, int index, bool reserved);

  // Occupancy, rebuilt each update: bit `slot` of (type U, place p) is set when robot `slot` holds
  // a place conflicting with U at p. The tables below are indexed by typed(U, p) too.
  std::size_t words_ = 1;
  std::vector<std::uint64_t> occupancy_;
  std::vector<std::vector<CorridorSpan>> spans_;  ///< by corridor
  std::vector<int> claim_place_;                  ///< slot of the waiting robot that reserved the place, -1 when none
  struct EntryClaim {
    int place = 0;
    double since = 0.0;                                              ///< first come, first in
    double lifted_until = -std::numeric_limits<double>::infinity();  ///< closure lifted before this
  };
  /// Waited `priority_wait`: other entrants defer to it (earlier_entry_claims).
  bool claim_in_line(int robot_id, const EntryClaim& claim, double now) const;
  /// In line and not lifted: its places are closed to robots from outside them.
  bool claim_active(int robot_id, const EntryClaim& claim, double now) const;
  /// Whether the robots in the way of an entry claim wait, down the line, on the claim itself
  /// (a robot it keeps out): then holding the closure would keep them waiting on each other.
  bool claim_waits_on_itself(int robot_id, const EntryClaim& claim) const;
  /// Whether `places[index]` is closed by an entry claim to a robot coming from before it.
  bool entry_closes(const std::vector<int>& places, int index, int type) const;
  std::map<int, EntryClaim> entries_;           ///< robots waiting beside the roads, by id
  std::vector<std::uint8_t> entry_closed_;      ///< places closed by an active entry claim
  std::map<int, std::vector<int>> area_waits_;  ///< standing robots waiting for their work area, by id
  /// Whether a robot may end its grant at `place`: not in another robot's way out (keep_clear).
  bool stop_kept_clear(const Robot& robot, int place) const;
  struct WayOut {
    geometry::Polygon area;
    std::vector<std::vector<int>> reach;  ///< by vehicle type: the places whose regions touch it, sorted
  };
  std::map<int, WayOut> ways_out_;  ///< keep_clear, by id
};

}  // namespace fleet::traffic
