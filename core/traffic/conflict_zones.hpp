#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"
#include "geometry/pose.hpp"
#include "map/road_graph.hpp"

namespace fleet::traffic {

/// A kind of vehicle as traffic sees it: a name and its footprint in the body frame (metres, any
/// simple polygon; the places are sized by its convex hull, as a region is a hull anyway).
struct VehicleType {
  std::string name;
  geometry::Polygon footprint;
  /// Body-frame x of the point that follows the route (a tricycle's rear axle; 0 for a body that
  /// keeps its centre on the route). Ahead of a point behind the centre, the body swings out of
  /// a curve: a place reserves the body with its centre there and with this point there.
  double tracking_x = 0.0;
  /// The footprint-centre poses of the vehicle driving a path from its first point, heading along
  /// its first segment, from rest or `at_speed`, as its own controller and body model drive it (a
  /// tricycle cuts inside a bend with its rear axle and swings its front wide). Unset: the body
  /// keeps its tracking point on the route. A place reserves these bodies through every bend.
  std::function<std::vector<geometry::Pose2>(const std::vector<geometry::Vec2>& path, bool at_speed)> drive = {};
  /// Whether it backs up along its lane when traffic makes room with it: a mecanum or
  /// differential body reverses in its own track, a tricycle pivots round first, sweeping the
  /// ground about it, and is only moved forwards.
  bool backs_up = true;
};

/// The rectangle `footprint` centred on the body origin, counter-clockwise, in the body frame.
geometry::Polygon rectangle_footprint(const geometry::Footprint& footprint);
/// Extent of a body-frame footprint across the body's x axis (its width), metres.
double footprint_width(const geometry::Polygon& footprint);
/// Extent of a body-frame footprint along the body's x axis (its length), metres.
double footprint_length(const geometry::Polygon& footprint);

/// How the shared resources of a road graph are sized. Fixed per ConflictZones instance.
struct ResourceParams {
  geometry::Footprint footprint;  ///< the one vehicle type when `vehicle_types` is empty
  /// The vehicle types that drive the graph, indexed by type number; empty: one type, `footprint`.
  std::vector<VehicleType> vehicle_types;
  /// Minimum gap kept between two robots' footprints, metres. Each resource's region is grown by
  /// half of it, so two robots holding non-conflicting resources stay at least this far apart.
  double margin = 0.03;
  /// Points closer than this are one physical place (the zero-length hand-over edges between
  /// roads), metres.
  double coincident_distance = 1e-4;
};

/// Where a stretch of one lane lies in conflict with the opposite lane of the same road (OpenDRIVE
/// lanes of opposite sign), for a pair of vehicle types: corridor indices [lo, hi] of this lane,
/// [other_lo, other_hi] of the other lane's corridor. `sign` is +1 when both corridors' indices
/// grow the same way in space, -1 when they grow against each other, 0 when the stretch is a
/// single place on either side.
struct OppositeLane {
  int corridor = 0;
  int sign = 0;
  int lo = 0, hi = 0;
  int other_lo = 0, other_hi = 0;
};

/// The resources robots reserve, derived once from a RoadGraph.
///
/// A resource is a *place*: a graph point, with the points coincident with it (road hand-overs)
/// merged in. The region of a place is where a robot's footprint can be while the robot is nearer
/// that place than any other along its route: for every edge touching the place, the convex hull
/// of the footprint at the place and at the edge's midpoint, heading along the edge, grown by
/// margin / 2. Two places conflict when their regions overlap. A robot driving from place a to b
/// is always inside region(a) or region(b), so holding both while it moves, and releasing a once
/// it is past the midpoint, keeps its body inside what it holds. Holding non-conflicting sets of
/// places therefore keeps robots `margin` apart, at junctions (where the regions of all arms
/// overlap) and between nearby parallel roads alike.
///
/// **Vehicle types.** Places are shared by every type; a place's region depends on who stands
/// there: type T's footprint swept as above. A conflict is a pair (type A at place p, type B at
/// place q) whose regions overlap, precomputed for every pair of types. The one-type accessors
/// (`conflicts(place)`, `region(place)`, ...) are those of type 0. A type steered by a point
/// behind its centre (`tracking_x`, a tricycle's rear axle) has that point on the route: in a
/// curve its centre leaves the route on the outside and its front swings wide. That body, placed
/// with the tracking point on each route point, joins the region of the place nearest its centre
/// forward along the road, where the robot's progress puts it. A type that gives its own
/// `drive` has that drive rolled through every bend, from rest and at speed, and each place
/// reserves the bodies nearest it.
///
/// Two derived facts drive the traffic rules:
/// - a *branch* place has three or more neighbouring places (a junction arm end); a place is not
///   *stoppable* for type T when T's region there overlaps a branch place's region of any type:
///   a robot waiting there would block the junction to some vehicle, so grants never end there
///   (except at the end of a route). `stoppable(place)` holds when it is stoppable for every type;
/// - *corridors* are the maximal chains of non-branch places (single-lane road stretches between
///   junctions, including corners). Each place knows its corridor and its index along it, so the
///   manager can tell the direction a robot drives a corridor and keep opposite directions apart.
class ConflictZones {
 public:
  ConflictZones(const map::RoadGraph& graph, const ResourceParams& params = {});

  std::size_t point_count() const { return place_of_.size(); }
  std::size_t place_count() const { return position_.size(); }
  std::size_t type_count() const { return types_.size(); }
  const std::vector<VehicleType>& vehicle_types() const { return types_; }
  int place_of(int point) const { return place_of_[static_cast<std::size_t>(point)]; }
  /// Places whose regions overlap `place`'s, sorted, including `place` itself (type 0 with itself).
  const std::vector<int>& conflicts(int place) const { return conflicts(0, place, 0); }
  /// Places q such that `other_type` at q conflicts with `type` at `place`, sorted, including
  /// `place` itself (two vehicles cannot stand on one point).
  const std::vector<int>& conflicts(int type, int place, int other_type) const {
    return conflicts_[pair_index(type, other_type)][static_cast<std::size_t>(place)];
  }
  bool conflict(int place_a, int place_b) const { return conflict(0, place_a, 0, place_b); }
  bool conflict(int type_a, int place_a, int type_b, int place_b) const;
  /// Stoppable for every vehicle type.
  bool stoppable(int place) const { return stoppable_all_[static_cast<std::size_t>(place)] != 0; }
  bool stoppable(int type, int place) const {
    return stoppable_[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)] != 0;
  }
  bool branch(int place) const { return branch_[static_cast<std::size_t>(place)] != 0; }
  /// Corridor of a non-branch place, -1 for a branch place.
  int corridor(int place) const { return corridor_[static_cast<std::size_t>(place)]; }
  int corridor_index(int place) const { return corridor_index_[static_cast<std::size_t>(place)]; }
  std::size_t corridor_count() const { return corridor_size_.size(); }
  bool corridor_is_loop(int corridor) const { return corridor_loop_[static_cast<std::size_t>(corridor)] != 0; }
  /// +1 or -1 for a step from place a to its neighbour b inside one corridor, 0 otherwise.
  int corridor_direction(int place_a, int place_b) const;
  geometry::Vec2 position(int place) const { return position_[static_cast<std::size_t>(place)]; }
  /// The region polygons of a place (for drawing and tests), of type 0 or of `type`.
  const std::vector<geometry::Polygon>& region(int place) const { return region(0, place); }
  const std::vector<geometry::Polygon>& region(int type, int place) const {
    return region_[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)];
  }
  /// Which move each of region(type, place)'s polygons is a body of: a robot coming from place
  /// `before` through the place and going on to `after` (a body centred on one edge: that edge's
  /// other end for both); -1: any move.
  struct RegionMove {
    int before = -1;
    int after = -1;
  };
  const std::vector<RegionMove>& region_moves(int type, int place) const {
    return region_move_[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)];
  }
  /// Whether `body` (convex, map frame) reaches into what a robot of `type` sweeps coming from
  /// place `from` into its neighbour `to` and through it: the polygons of `to` of the moves that
  /// come from `from` (every way on from there included). A body beside the roads may reach into a
  /// place's region for some ways through it and not others: a truck turning onto a lane swings
  /// over the stall beside it, one driving straight through does not.
  bool body_reaches_move(const geometry::Polygon& body, int type, int from, int to) const;
  /// False when a body inside `body` cannot reach any region of `place` for `type`: every region
  /// lies within reach(type, place) of the place's position, so circles apart rule it out without
  /// the polygon tests.
  bool may_reach(const geometry::BoundingCircle& body, int type, int place) const;
  /// The opposite lanes of `corridor` whose places conflict with it for `type` on `corridor` and
  /// `other_type` on the opposite lane (two lanes of one road: see OppositeLane).
  /// Whether any pair of lanes of one road conflicts (opposite_lanes is empty everywhere if not).
  bool has_opposite_lanes() const { return has_opposite_lanes_; }
  const std::vector<OppositeLane>& opposite_lanes(int type, int corridor, int other_type) const {
    return opposite_[pair_index(type, other_type)][static_cast<std::size_t>(corridor)];
  }
  /// Metres from its position the region of `place` for vehicle `type` reaches.
  double reach(int type, int place) const {
    return reach_[static_cast<std::size_t>(type)][static_cast<std::size_t>(place)];
  }
  /// Undirected neighbour places.
  const std::vector<int>& neighbours(int place) const { return neighbours_[static_cast<std::size_t>(place)]; }
  const ResourceParams& params() const { return params_; }

 private:
  std::size_t pair_index(int type, int other_type) const {
    return static_cast<std::size_t>(type) * types_.size() + static_cast<std::size_t>(other_type);
  }
  /// Directed adjacency of places (coincident hand-over points are one place), sorted.
  struct PlaceLinks {
    std::vector<std::vector<int>> successors, predecessors;
  };
  PlaceLinks place_links(const map::RoadGraph& graph) const;
  void build_places(const map::RoadGraph& graph, std::vector<std::vector<int>>& members);
  void build_regions(const map::RoadGraph& graph, const std::vector<std::vector<int>>& adjacent,
                     const std::vector<std::vector<int>>& members, std::size_t type);
  void add_tracked_bodies(const map::RoadGraph& graph, const std::vector<std::vector<int>>& adjacent,
                          const geometry::Polygon& body, double lead, std::size_t type);
  void update_reach(std::size_t type);
  void add_driven_bodies(const map::RoadGraph& graph, const geometry::Polygon& body, std::size_t type);
  void build_conflicts(std::size_t type_a, std::size_t type_b);
  void build_stoppable(const std::vector<std::vector<int>>& successors,
                       const std::vector<std::vector<int>>& predecessors);
  void build_corridors();
  void build_opposite_lanes(const map::RoadGraph& graph, const std::vector<std::vector<int>>& members);

  ResourceParams params_;
  std::vector<VehicleType> types_;
  std::vector<int> place_of_;
  std::vector<geometry::Vec2> position_;
  std::vector<std::vector<int>> neighbours_;
  std::vector<std::vector<std::vector<geometry::Polygon>>> region_;  ///< by type, by place
  std::vector<std::vector<std::vector<RegionMove>>> region_move_;    ///< by type, by place, as region_
  std::vector<std::vector<double>> reach_;                           ///< by type, by place
  std::vector<std::vector<std::vector<int>>> conflicts_;             ///< by pair of types, by place
  std::vector<std::vector<std::vector<OppositeLane>>> opposite_;     ///< by pair of types, by corridor
  std::vector<std::uint8_t> branch_;
  std::vector<std::vector<std::uint8_t>> stoppable_;  ///< by type
  std::vector<std::uint8_t> stoppable_all_;
  bool has_opposite_lanes_ = false;
  std::vector<int> corridor_;
  std::vector<int> corridor_index_;
  std::vector<int> corridor_size_;
  std::vector<std::uint8_t> corridor_loop_;
};

/// A convex counter-clockwise polygon with every edge moved out by `grow` (mitred corners): a
/// rectangle grows by `grow` on every side, as geometry::footprint_polygon grows it.
geometry::Polygon grown(const geometry::Polygon& convex, double grow);

/// Convex hull (Andrew's monotone chain), counter-clockwise, without collinear points.
geometry::Polygon convex_hull(std::vector<geometry::Vec2> points);

}  // namespace fleet::traffic
