#pragma once

#include <cstdint>
#include <vector>

#include "coordination/body_closures.hpp"
#include "coordination/place_graph.hpp"
#include "coordination/place_pibt.hpp"
#include "coordination/place_route.hpp"
#include "coordination/visit_order.hpp"
#include "geometry/polygon.hpp"
#include "map/road_graph.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

struct PlaceTrafficParams {
  /// Sim seconds between plan steps: about the time a robot takes for a typical move. 0: the mean
  /// move between neighbouring places at `speed`.
  double plan_period_s = 0.0;
  double speed = 0.2;  ///< m/s, the robots' cruising speed (for plan_period_s 0)
  /// Moves a robot's plan may run ahead of where it is: one this far behind is held in the plan.
  int plan_ahead = 4;
  std::uint64_t seed = 1;
};

/// What traffic grants a robot on the roads.
struct PlaceGrant {
  std::uint64_t version = 0;  ///< the route the grant is for
  /// The last point of that route the robot may drive to; -1: it stands where it is (it waits to
  /// be let onto the roads).
  int granted_index = -1;
  double granted_distance = 0.0;  ///< metres along the route to that point
  /// Non-empty: the robot drives these graph points instead of its own route, as `version`.
  std::vector<int> route;
  /// The robots it waits for: whose visits are ordered before its next one, whose bodies close
  /// its way on, whose places the plan keeps it standing for, or whom its look-ahead stops it for.
  std::vector<int> waits_for;
  bool arrived = false;  ///< at its route's end
};

/// The road-site coordination core as the live fleet drives it: robots report the routes they
/// drive (road graph points) and how far along they are, or where their bodies stand beside the
/// roads; PlacePibt plans every robot's next places together each plan step, from its last planned
/// place towards its route's end, and the VisitOrder of those plans says how far each robot may
/// drive [Hönig 2019, section IV]: up to the last of its planned visits none of whose earlier
/// conflicting visits is still open. A plan that leaves a robot's route hands it a new route (its
/// visits, then a shortest way on to its route's end). A robot standing without a route (working
/// beside the roads, lost) closes the places its body reaches to new plans. A robot enters the
/// roads where its route starts once no other robot's open or planned visit conflicts with that
/// place. Free of DDS: server::TrafficControl carries its grants out.
class PlaceTraffic {
 public:
  PlaceTraffic(const map::RoadGraph& graph, const traffic::ConflictZones& zones, const PlaceTrafficParams& params);

  /// A robot of vehicle type `type` (the zones' numbering); returns its number (0, 1, ...).
  int add_robot(int type);
  int robots() const { return static_cast<int>(robots_.size()); }
  /// The robot drives route `version` along road graph `points`, `progress` metres from its first.
  /// Versions older than the robot's current one are ignored. False (nothing changes) when a
  /// point is not on the graph or the route is empty. `way_out` (convex, map frame; empty when
  /// none) is what its body sweeps from beside the roads onto the route's start: it enters once
  /// no other robot's visit or body is in it, and holds it until it is on the road (sent empty).
  bool drive(int robot, std::uint64_t version, const std::vector<int>& points, double progress,
             const geometry::Polygon& way_out = {});
  /// The body of a robot waiting to enter the roads, as it stands beside them: it closes the
  /// places it reaches, as a standing body does. Ignored for a robot on the roads or standing.
  void waiting_body(int robot, const geometry::Polygon& body);
  /// The robot stands without a route with body `body` (a convex polygon, map frame; empty when
  /// unknown or off the roads): it holds the places its body reaches until it drives again.
  /// `to_sweep` (convex; empty when none) is the area of a manoeuvre beside the roads it waits to
  /// begin: held as a way out is, robots in it are pushed out of it.
  void stand(int robot, const geometry::Polygon& body, const geometry::Polygon& to_sweep = {});
  /// The robot's own look-ahead has stopped it for these robots' bodies for a while
  /// (TrafficRoute::stopped_for; empty when it drives on): whatever its grant, it does not move
  /// closer to them. It is planned to stay, its visits not yet begun are dropped, so robots whose
  /// visits wait for those go first, and it waits for the robots named.
  void stopped_for(int robot, std::vector<int> others);
  /// Robots other than `robot` whose visits, begun or planned, are of places `area` (convex, map
  /// frame) reaches for their vehicle type, or whose standing bodies overlap it: those a
  /// manoeuvre sweeping `area` beside the roads must wait for.
  std::vector<int> robots_in_area(int robot, const geometry::Polygon& area) const;
  /// One cycle at sim time `now`: a plan step when one is due, then every robot's grant.
  void update(double now);

  const PlaceGrant& grant(int robot) const { return at(robot).grant; }
  /// Whether the robot is on the roads in the plan (driving a route it was let onto).
  bool on_roads(int robot) const { return order_.present(robot); }
  /// The places its visits are of, from the one its body is in on.
  std::vector<int> places_ahead(int robot) const { return order_.places_ahead(robot); }
  /// Robots of a wait-for cycle among the visits, empty when none (the order's promise: none).
  std::vector<int> wait_cycle() const { return order_.wait_cycle(); }
  std::size_t plan_steps() const { return plan_step_; }
  double plan_period_s() const { return params_.plan_period_s; }
  const traffic::ConflictZones& zones() const { return zones_; }

 private:
  enum class Mode { kOff, kStanding, kWaitingToEnter, kDriving };
  /// A robot and the route it drives (version `version`).
  struct Robot : PlaceRoute {
    int type = 0;
    Mode mode = Mode::kOff;
    std::uint64_t version = 0;
    int at = 0;                    ///< index into `places` of the robot's current visit
    double progress = 0.0;         ///< metres along the route, as last reported
    bool adopted = true;           ///< it drives `version` (false: a new route is on its way to it)
    bool moved_off_route = false;  ///< its last planned move left the route it had (the plan's choice)
    geometry::Polygon body;        ///< standing without a route, or waiting to enter
    /// What its body sweeps beside the roads: its way onto them (held until it is on the road), or
    /// the area of a manoeuvre it waits to begin.
    geometry::Polygon way_out;
    std::uint64_t waiting_since = 0;  ///< the order in which robots began to wait to enter
    std::vector<int> entry_blockers;  ///< waiting to enter: the robots in its way
    /// Waiting to enter with robots in its way that wait for it in turn: the places conflicting
    /// with where it enters are closed to the others, and those in them are pushed out.
    bool reserves_entry = false;
    std::vector<int> stopped_for;  ///< robots its own look-ahead stops it for
    /// The last plan kept it standing: the robots standing or planned at places conflicting with
    /// its route's next place.
    std::vector<int> kept_by;
    PlaceGrant grant;
  };
  Robot& at(int robot) { return robots_[static_cast<std::size_t>(robot)]; }
  const Robot& at(int robot) const { return robots_[static_cast<std::size_t>(robot)]; }

  /// Takes a route the robot drives now (or waits to enter the roads by).
  void take_route(int robot, std::uint64_t version, const std::vector<int>& points, double progress);
  /// Lets a robot waiting beside the roads onto them where its route continues, when free.
  void try_to_enter(int robot);
  /// The body the robot stands with beside the roads (standing or waiting to enter): it closes
  /// the places it reaches, and visits planned into them that have not begun are dropped.
  void take_body(int robot, const geometry::Polygon& body);
  /// Holds (or, empty, releases) the robot's way out onto the roads.
  void hold_way_out(int robot, const geometry::Polygon& way_out);
  /// The body that closes places to others: standing or waiting to enter; empty otherwise.
  static const geometry::Polygon& closing_body(const Robot& r);
  /// Robots other than `robot` (of `type`, its last planned place `from`, -1 off the roads) whose
  /// bodies or ways out close `place` to it.
  std::vector<int> closers_of(int robot, int type, int place, int from) const;
  /// The robots a plan step that keeps `robot` standing keeps it for: those whose place or next
  /// place conflicts with the place its route leads on to (none when the plan moves it, or it is
  /// held, or has no errand). `stands` and `goes`: per place, the robot planned from it and the
  /// robot planned into it, -1.
  std::vector<int> kept_by(int robot, const std::vector<PlaceRobot>& planned, const std::vector<int>& next,
                           const std::vector<int>& stands, const std::vector<int>& goes) const;
  /// The place of the robot's current visit, then those it is about to drive into: its planned
  /// visits, and its route's on from the last of them, as far as one body length.
  std::vector<int> way_ahead(int robot) const;
  /// The robot stands at `place` in the order: others' plans into places conflicting with it go.
  void place_robot(int robot, int place);
  /// Drops the visits other robots have planned, not begun, into places `conflicts` accepts.
  template <typename Conflicts>
  void drop_visits_into(int robot, const Conflicts& conflicts);
  /// Ends visits the robot's progress shows it has driven through.
  void follow_progress(int robot, double progress);
  void plan_step();
  /// Sets Robot::reserves_entry of the robots waiting to enter, and closes what they hold.
  void reserve_entries();
  /// How many of the robot's visits after its current one its last grant lets it drive into.
  static int granted_visits(const Robot& r);
  /// The plan moved the robot off its route: a new route through its visits to the route's end.
  void reroute(int robot);
  /// The graph point a route through the robot's visits starts at, of `place` (its current visit's).
  int first_point(const Robot& r, int place) const;
  /// Graph points along consecutive places, starting at `from_point` (a point of places[0]).
  std::vector<int> points_along(int from_point, const std::vector<int>& places) const;
  void update_grant(int robot);
  /// The places closed by what robots beside the roads close (BodyClosures::rebuild).
  void rebuild_closed();

  const map::RoadGraph& graph_;
  const traffic::ConflictZones& zones_;
  PlaceTrafficParams params_;
  PlaceGraph places_;
  PlacePibt planner_;
  VisitOrder order_;
  std::vector<Robot> robots_;
  std::vector<std::vector<int>> points_of_place_;
  std::vector<double> body_length_;  ///< per vehicle type: its footprint's length
  BodyClosures closures_;
  bool closed_stale_ = false;
  std::uint64_t waits_begun_ = 0;
  double next_plan_ = -1.0;
  std::size_t plan_step_ = 0;
};

}  // namespace fleet::coordination
