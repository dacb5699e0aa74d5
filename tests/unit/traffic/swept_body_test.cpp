// A stacker's pursuit does not keep its rear axle on a tight bend: the axle cuts inside, the
// heading lags the lane's past the bend and the front swings over the lane beside. Its places
// reserve what its own drive sweeps through every bend, so a robot on the lane beside is never
// granted where the turning stacker will swing, nor the turn while a robot stands there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "control/tricycle_sweep.hpp"
#include "geometry/polygon.hpp"
#include "outside_regions.hpp"
#include "test_graphs.hpp"
#include "traffic/conflict_zones.hpp"
#include "vehicle/vehicle_types.hpp"

namespace fleet::traffic {
namespace {

using testing::GraphBuilder;

constexpr int kTracked = 0;  // the stacker steered by its rear axle, without its drive
constexpr int kDriven = 1;   // the same, with its drive through the bends
constexpr int kTruck = 2;    // a reach truck's body on the lane beside
constexpr double kRadius = 1.0;
constexpr double kBeside = 1.49;  // the plant's lanes of one corridor, centre to centre

const vehicle::VehicleProfile& stacker() {
  return vehicle::find_robot_type("stacker")->defaults;
}

std::vector<geometry::Pose2> drive(const std::vector<geometry::Vec2>& path, bool at_speed) {
  return control::drive_along(control::tricycle_drive_for(stacker()), path, at_speed);
}

ResourceParams stacker_types() {
  ResourceParams p;
  p.margin = 0.1;
  const geometry::Polygon body = stacker().footprint;
  const double axle = stacker().rear_axle_x;
  p.vehicle_types = {{"tracked", body, axle},
                     {"driven", body, axle, [](const auto& path, bool at_speed) { return drive(path, at_speed); }},
                     {"truck", rectangle_footprint({1.6, 0.9})}};
  return p;
}

// Southwards along x = 0 from y = 6, a right turn of radius 1 m into a lane westwards along
// y = 0 (an aisle into a corridor's lane, as on the plant), and the corridor's other lane,
// eastwards along y = -kBeside. Points 0.5 m apart on the lanes, 0.25 m round the turn.
struct CornerSite {
  map::RoadGraph graph;
  std::vector<int> turn;  // the turning robot's route, in driving order
};

CornerSite corner_site() {
  GraphBuilder b;
  CornerSite site;
  site.turn = b.one_way_road(0.0, 6.0, 0.0, kRadius, 0.5);
  constexpr int kSteps = 6;
  for (int k = 1; k <= kSteps; ++k) {
    const double theta = -std::numbers::pi / 2 * k / kSteps;
    const int p = b.point(-kRadius + kRadius * std::cos(theta), kRadius + kRadius * std::sin(theta));
    b.arc(site.turn.back(), p);
    site.turn.push_back(p);
  }
  const auto west = b.one_way_road(-kRadius - 0.5, 0.0, -9.0, 0.0, 0.5);
  b.arc(site.turn.back(), west.front());
  site.turn.insert(site.turn.end(), west.begin(), west.end());
  b.one_way_road(-9.0, -kBeside, 3.0, -kBeside, 0.5);
  site.graph = b.graph();
  return site;
}

std::vector<geometry::Vec2> positions(const map::RoadGraph& g, const std::vector<int>& points) {
  std::vector<geometry::Vec2> out;
  for (int p : points)
    out.push_back({g.points[static_cast<std::size_t>(p)].x, g.points[static_cast<std::size_t>(p)].y});
  return out;
}

// How far the stacker's body leaves the regions of its route's places for `type`, driven from
// rest 5 m before the bend, through it and 6 m on.
double worst_outside(const ConflictZones& zones, const CornerSite& site, int type) {
  std::vector<const geometry::Polygon*> reserved;
  for (int point : site.turn) {
    for (const auto& region : zones.region(type, zones.place_of(point))) reserved.push_back(&region);
  }
  double worst = 0.0;
  for (const geometry::Pose2& centre : drive(positions(site.graph, site.turn), false)) {
    // The drive ends with its rear axle, not its centre, on the route's end.
    if (centre.x < -7.0) break;
    const geometry::Polygon body = geometry::footprint_polygon(centre, stacker().extent());
    worst = std::max(worst, test::outside(body, reserved));
  }
  return worst;
}

TEST(SweptBody, TheStackerDrivenThroughABendStaysInsideThePlacesOfItsRoute) {
  const CornerSite site = corner_site();
  const ConflictZones zones(site.graph, stacker_types());
  EXPECT_GT(worst_outside(zones, site, kTracked), 0.05) << "the bend is too wide to show anything";
  EXPECT_LT(worst_outside(zones, site, kDriven), 0.01);
}

TEST(SweptBody, AnyPlaceOnTheLaneBesideThatTheSwingReachesConflictsWithTheTurn) {
  const CornerSite site = corner_site();
  const ConflictZones zones(site.graph, stacker_types());
  std::vector<int> turn_places;
  for (int point : site.turn) turn_places.push_back(zones.place_of(point));
  const auto conflicts_with_turn = [&](int type, int beside) {
    return std::any_of(turn_places.begin(), turn_places.end(),
                       [&](int p) { return zones.conflict(type, p, kTruck, beside); });
  };
  int only_when_driven = 0;
  for (std::size_t i = 0; i < site.graph.points.size(); ++i) {
    if (std::abs(site.graph.points[i].y + kBeside) > 1e-9) continue;
    const int beside = zones.place_of(static_cast<int>(i));
    // Reserving more never reserves less.
    if (conflicts_with_turn(kTracked, beside)) {
      EXPECT_TRUE(conflicts_with_turn(kDriven, beside));
    }
    if (conflicts_with_turn(kDriven, beside) && !conflicts_with_turn(kTracked, beside)) ++only_when_driven;
  }
  EXPECT_GT(only_when_driven, 0) << "the swing past the bend reaches no place beside";
}

TEST(SweptBody, WhereRobotsMayWaitDoesNotDependOnTheDrive) {
  const CornerSite site = corner_site();
  ResourceParams without = stacker_types();
  without.vehicle_types[kDriven].drive = nullptr;
  const ConflictZones with_drive(site.graph, stacker_types());
  const ConflictZones without_drive(site.graph, without);
  for (int type : {kTracked, kDriven, kTruck}) {
    for (std::size_t p = 0; p < with_drive.place_count(); ++p) {
      EXPECT_EQ(with_drive.stoppable(type, static_cast<int>(p)), without_drive.stoppable(type, static_cast<int>(p)))
          << "type " << type << ", place " << p;
    }
  }
}

}  // namespace
}  // namespace fleet::traffic
