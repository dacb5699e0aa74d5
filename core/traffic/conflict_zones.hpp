#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "geometry/polygon.hpp"
#include "map/road_graph.hpp"

namespace fleet::traffic {

/// How the shared resources of a road graph are sized. Fixed per ConflictZones instance.
struct ResourceParams {
  geometry::Footprint footprint;  ///< the largest robot that drives the graph
  /// Minimum gap kept between two robots' footprints, metres. Each resource's region is grown by
  /// half of it, so two robots holding non-conflicting resources stay at least this far apart.
  double margin = 0.03;
  /// Points closer than this are one physical place (the zero-length hand-over edges between
  /// roads), metres.
  double coincident_distance = 1e-6;
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
/// Two derived facts drive the traffic rules:
/// - a *branch* place has three or more neighbouring places (a junction arm end); a place whose
///   region overlaps a branch place's is not *stoppable*: a robot waiting there would block the
///   junction, so grants never end there (except at the end of a route);
/// - *corridors* are the maximal chains of non-branch places (single-lane road stretches between
///   junctions, including corners). Each place knows its corridor and its index along it, so the
///   manager can tell the direction a robot drives a corridor and keep opposite directions apart.
class ConflictZones {
 public:
  ConflictZones(const map::RoadGraph& graph, const ResourceParams& params = {});

  std::size_t point_count() const { return place_of_.size(); }
  std::size_t place_count() const { return conflicts_.size(); }
  int place_of(int point) const { return place_of_[static_cast<std::size_t>(point)]; }
  /// Places whose regions overlap `place`'s, sorted, including `place` itself.
  const std::vector<int>& conflicts(int place) const { return conflicts_[static_cast<std::size_t>(place)]; }
  bool conflict(int place_a, int place_b) const;
  bool stoppable(int place) const { return stoppable_[static_cast<std::size_t>(place)] != 0; }
  bool branch(int place) const { return branch_[static_cast<std::size_t>(place)] != 0; }
  /// Corridor of a non-branch place, -1 for a branch place.
  int corridor(int place) const { return corridor_[static_cast<std::size_t>(place)]; }
  int corridor_index(int place) const { return corridor_index_[static_cast<std::size_t>(place)]; }
  std::size_t corridor_count() const { return corridor_size_.size(); }
  bool corridor_is_loop(int corridor) const { return corridor_loop_[static_cast<std::size_t>(corridor)] != 0; }
  /// +1 or -1 for a step from place a to its neighbour b inside one corridor, 0 otherwise.
  int corridor_direction(int place_a, int place_b) const;
  geometry::Vec2 position(int place) const { return position_[static_cast<std::size_t>(place)]; }
  /// The region polygons of a place (for drawing and tests).
  const std::vector<geometry::Polygon>& region(int place) const { return region_[static_cast<std::size_t>(place)]; }
  /// Undirected neighbour places.
  const std::vector<int>& neighbours(int place) const { return neighbours_[static_cast<std::size_t>(place)]; }
  const ResourceParams& params() const { return params_; }

 private:
  ResourceParams params_;
  std::vector<int> place_of_;
  std::vector<geometry::Vec2> position_;
  std::vector<std::vector<int>> neighbours_;
  std::vector<std::vector<geometry::Polygon>> region_;
  std::vector<std::vector<int>> conflicts_;
  std::vector<std::uint8_t> branch_;
  std::vector<std::uint8_t> stoppable_;
  std::vector<int> corridor_;
  std::vector<int> corridor_index_;
  std::vector<int> corridor_size_;
  std::vector<std::uint8_t> corridor_loop_;
};

/// Convex hull (Andrew's monotone chain), counter-clockwise, without collinear points.
geometry::Polygon convex_hull(std::vector<geometry::Vec2> points);

}  // namespace fleet::traffic
