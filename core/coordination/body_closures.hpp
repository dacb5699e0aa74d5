#pragma once

#include <vector>

#include "coordination/place_index.hpp"
#include "coordination/place_pibt.hpp"
#include "geometry/polygon.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::coordination {

/// What a robot beside the roads closes to the others: its body (standing, or waiting to enter),
/// the area it sweeps onto them or waits to manoeuvre in, and where it enters when it holds that.
struct BesideTheRoads {
  int type = 0;
  const geometry::Polygon* body = nullptr;     ///< empty or null: none
  const geometry::Polygon* way_out = nullptr;  ///< empty or null: none
  int held_entry = -1;                         ///< the place it enters at and holds; -1: none
};

/// The places that bodies and areas beside the roads close, for each vehicle type
/// (ClosedPlaces), built from where the robots stand: a body closes the places its body reaches,
/// each only to the moves into it whose swept bodies it reaches
/// (traffic::ConflictZones::body_reaches_move); an area, or a held entry, closes the places it
/// reaches (or that conflict with the entry) to robots outside it.
class BodyClosures {
 public:
  explicit BodyClosures(const traffic::ConflictZones& zones);

  /// Builds the closed places again from every robot's state (indexed by robot number).
  void rebuild(const std::vector<BesideTheRoads>& robots);
  const ClosedPlaces& closed() const { return closed_; }
  /// The robot closing `place` to `robot` (of `type`, at place `from`, -1 off the roads), kOpen
  /// when none does (ClosedPlaces::closer).
  int closer(int type, int place, int robot, int from) const { return closed_.closer(type, place, robot, from); }

  /// A circle round a body: places farther than it reaches are skipped without a polygon test.
  struct Circle {
    geometry::Vec2 centre;
    double radius = 0.0;
  };
  static Circle circle_around(const geometry::Polygon& body);
  /// Whether a body (convex, map frame) reaches into the region of `place` for vehicle `type`.
  bool reaches(const geometry::Polygon& body, int type, int place) const;
  /// The same with the body's circle computed once for many places.
  bool reaches(const geometry::Polygon& body, const Circle& around, int type, int place) const;
  /// Places whose region, for some type, may reach within the circle.
  std::vector<int> places_near(const Circle& around) const { return index_.near(around.centre, around.radius); }

 private:
  /// Marks the places `polygon` reaches in `layer` as closed by `robot`.
  void close(std::vector<std::vector<int>>& layer, int robot, const geometry::Polygon& polygon);
  /// Closes the places a body reaches (by_body), and of the moves into them those whose swept
  /// bodies it reaches (by_move).
  void close_to_moves(int robot, const geometry::Polygon& body);

  const traffic::ConflictZones& zones_;
  PlaceIndex index_;
  ClosedPlaces closed_;
};

}  // namespace fleet::coordination
