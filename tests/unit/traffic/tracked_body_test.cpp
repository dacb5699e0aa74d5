// A vehicle steered by its rear axle (the stacker) keeps that axle on the route: in a curve its
// centre leaves the route on the outside and its front swings over the lane beside. Its places
// reserve that swept body, so a robot on the lane beside is never granted into it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "geometry/polygon.hpp"
#include "test_graphs.hpp"
#include "traffic/conflict_zones.hpp"

namespace fleet::traffic {
namespace {

using testing::GraphBuilder;
using testing::point_at;

constexpr int kCentred = 0;  // the stacker's footprint, steered by its centre
constexpr int kTracked = 1;  // the same footprint, steered by its rear axle 0.75 m behind the centre
constexpr int kSmall = 2;    // a small robot on the lane beside
constexpr double kLead = 0.75;
constexpr double kRadius = 1.5;

ResourceParams stacker_types() {
  ResourceParams p;
  p.margin = 0.05;
  const geometry::Polygon stacker = rectangle_footprint({1.7, 0.748});
  p.vehicle_types = {{"centred", stacker}, {"tracked", stacker, -kLead}, {"small", rectangle_footprint({0.3, 0.2})}};
  return p;
}

// Southwards along x = 0 from y = 5, a right turn of radius 1.5 m about (-1.5, 1.5), then
// westwards along y = 0 to x = -6; and a lane beside it on the outside of the turn, eastwards
// along y = -`beside`. Every point 0.1 m apart.
struct TurnSite {
  map::RoadGraph graph;
  std::vector<int> turn;  // the turning lane's points in driving order
};

TurnSite turn_site(double beside) {
  GraphBuilder b;
  TurnSite site;
  const auto south = b.road(0.0, 5.0, 0.0, 1.5);
  site.turn = south;
  const int steps = static_cast<int>(std::lround(kRadius * std::numbers::pi / 2 / 0.1));
  for (int k = 1; k <= steps; ++k) {
    const double theta = -std::numbers::pi / 2 * k / steps;
    const int p = b.point(-kRadius + kRadius * std::cos(theta), kRadius + kRadius * std::sin(theta));
    b.link(site.turn.back(), p);
    site.turn.push_back(p);
  }
  const auto west = b.road(-kRadius - 0.1, 0.0, -6.0, 0.0);
  b.link(site.turn.back(), west.front());
  site.turn.insert(site.turn.end(), west.begin(), west.end());
  b.road(-6.0, -beside, 2.0, -beside);
  site.graph = b.graph();
  return site;
}

// The places of the lane beside (type small) that the body touches.
std::vector<int> touched_beside(const ConflictZones& zones, const map::RoadGraph& g, double beside,
                                const geometry::Polygon& body) {
  std::vector<int> touched;
  for (std::size_t i = 0; i < g.points.size(); ++i) {
    if (std::abs(g.points[i].y + beside) > 1e-9) continue;
    const int q = zones.place_of(static_cast<int>(i));
    for (const auto& r : zones.region(kSmall, q)) {
      if (geometry::convex_polygons_overlap(r, body)) {
        touched.push_back(q);
        break;
      }
    }
  }
  return touched;
}

TEST(TrackedBody, EveryPlaceBesideThatTheSwungOutBodyTouchesConflictsWithThePlaceItsProgressIsIn) {
  constexpr double kBeside = 1.05;
  const TurnSite site = turn_site(kBeside);
  const ConflictZones zones(site.graph, stacker_types());
  int touching = 0, missed_when_centred = 0;
  // The rear axle on each point of the turning lane, heading along the lane there.
  for (std::size_t k = 0; k + 1 < site.turn.size(); ++k) {
    const auto& a = site.graph.points[static_cast<std::size_t>(site.turn[k])];
    const auto& b = site.graph.points[static_cast<std::size_t>(site.turn[k + 1])];
    const double heading = std::atan2(b.y - a.y, b.x - a.x);
    const geometry::Pose2 centre{a.x + kLead * std::cos(heading), a.y + kLead * std::sin(heading), heading};
    const geometry::Polygon body = geometry::footprint_polygon(centre, {1.7, 0.748});
    // Progress is measured at the centre: the robot is at the route point nearest it.
    std::size_t nearest = k;
    for (std::size_t j = k; j < site.turn.size(); ++j) {
      const auto& p = site.graph.points[static_cast<std::size_t>(site.turn[j])];
      const auto& n = site.graph.points[static_cast<std::size_t>(site.turn[nearest])];
      if (std::hypot(p.x - centre.x, p.y - centre.y) < std::hypot(n.x - centre.x, n.y - centre.y)) nearest = j;
    }
    const int held = zones.place_of(site.turn[nearest]);
    for (int q : touched_beside(zones, site.graph, kBeside, body)) {
      ++touching;
      EXPECT_TRUE(zones.conflict(kTracked, held, kSmall, q)) << "rear axle at (" << a.x << ", " << a.y << ")";
      if (!zones.conflict(kCentred, held, kSmall, q)) ++missed_when_centred;
    }
  }
  ASSERT_GT(touching, 0) << "the lane beside is out of the swung body's reach: the test shows nothing";
  EXPECT_GT(missed_when_centred, 0) << "a body centred on the route reaches the lane beside as well";
}

TEST(TrackedBody, OnAStraightRoadItsPlacesConflictAsACentredBodys) {
  // Points 0.47 m apart, as on the plant: the centre, 0.75 m ahead of the axle, falls between
  // two of them, still on the road.
  GraphBuilder b;
  b.road(0.0, 0.0, 9.4, 0.0, 0.47);
  b.road(0.0, 1.05, 9.4, 1.05, 0.47);
  const ConflictZones zones(b.graph(), stacker_types());
  for (double x : {3.76, 4.23, 4.7}) {
    const int p = zones.place_of(point_at(b.graph(), x, 0.0));
    EXPECT_EQ(zones.conflicts(kTracked, p, kSmall), zones.conflicts(kCentred, p, kSmall)) << "x = " << x;
    EXPECT_EQ(zones.conflicts(kTracked, p, kTracked), zones.conflicts(kCentred, p, kCentred)) << "x = " << x;
  }
}

}  // namespace
}  // namespace fleet::traffic
