#include "traffic/conflict_zones.hpp"

#include <gtest/gtest.h>

#include <string>

#include "map/site_map.hpp"
#include "test_graphs.hpp"
#include "test_paths.hpp"

namespace fleet::traffic {
namespace {

using testing::GraphBuilder;
using testing::point_at;

TEST(ConflictZones, ConflictsAlongARoadFollowTheFootprintLength) {
  GraphBuilder b;
  b.road(0.0, 0.0, 2.0, 0.0);
  const ConflictZones zones(b.graph());
  const int p0 = zones.place_of(point_at(b.graph(), 1.0, 0.0));
  // Region half length along the road: 0.125 (footprint) + 0.05 (half edge) + 0.015 (margin / 2).
  EXPECT_TRUE(zones.conflict(p0, zones.place_of(point_at(b.graph(), 1.3, 0.0))));
  EXPECT_FALSE(zones.conflict(p0, zones.place_of(point_at(b.graph(), 1.4, 0.0))));
  EXPECT_TRUE(zones.conflict(p0, p0));
  EXPECT_EQ(zones.conflict(p0, zones.place_of(point_at(b.graph(), 0.7, 0.0))),
            zones.conflict(zones.place_of(point_at(b.graph(), 0.7, 0.0)), p0));
}

TEST(ConflictZones, NearbyParallelRoadsConflictAndDistantOnesDoNot) {
  GraphBuilder b;
  b.road(0.0, 0.0, 1.0, 0.0);
  b.road(0.0, 0.15, 1.0, 0.15);
  b.road(0.0, 0.45, 1.0, 0.45);
  const ConflictZones zones(b.graph());
  const int low = zones.place_of(point_at(b.graph(), 0.5, 0.0));
  EXPECT_TRUE(zones.conflict(low, zones.place_of(point_at(b.graph(), 0.5, 0.15))));
  EXPECT_FALSE(
      zones.conflict(zones.place_of(point_at(b.graph(), 0.5, 0.15)), zones.place_of(point_at(b.graph(), 0.5, 0.45))));
}

TEST(ConflictZones, CoincidentPointsAreOnePlace) {
  map::RoadGraph g;
  for (int i = 0; i < 4; ++i) {
    map::GraphPoint p;
    p.id = i;
    p.x = i < 2 ? 0.1 * i : 0.1 * (i - 1);  // points 1 and 2 coincide: a road hand-over
    g.points.push_back(p);
    g.successors.emplace_back();
  }
  g.successors[0] = {1};
  g.successors[1] = {2};
  g.successors[2] = {3};
  const ConflictZones zones(g);
  EXPECT_EQ(zones.place_count(), 3u);
  EXPECT_EQ(zones.place_of(1), zones.place_of(2));
  EXPECT_NE(zones.place_of(0), zones.place_of(3));
}

TEST(ConflictZones, JunctionZonesAreNotStoppableAndSplitCorridors) {
  const map::RoadGraph g = testing::corridor_with_siding();
  const ConflictZones zones(g);
  const int branch = zones.place_of(point_at(g, 0.5, 0.0));
  EXPECT_TRUE(zones.branch(branch));
  EXPECT_FALSE(zones.stoppable(branch));
  EXPECT_FALSE(zones.stoppable(zones.place_of(point_at(g, 0.7, 0.0))));
  EXPECT_TRUE(zones.stoppable(zones.place_of(point_at(g, 1.0, 0.0))));
  EXPECT_TRUE(zones.stoppable(zones.place_of(point_at(g, 0.5, 0.5))));
  EXPECT_EQ(zones.corridor_count(), 3u);
  const int a = zones.place_of(point_at(g, 1.0, 0.0));
  const int c = zones.place_of(point_at(g, 1.1, 0.0));
  EXPECT_NE(zones.corridor_direction(a, c), 0);
  EXPECT_EQ(zones.corridor_direction(a, c), -zones.corridor_direction(c, a));
  EXPECT_EQ(zones.corridor(a), zones.corridor(zones.place_of(point_at(g, 2.0, 0.0))));
  EXPECT_NE(zones.corridor(a), zones.corridor(zones.place_of(point_at(g, 0.2, 0.0))));
  EXPECT_EQ(zones.corridor_direction(a, branch), 0);
}

TEST(ConflictZones, RejectsBadParams) {
  ResourceParams params;
  params.margin = -0.1;
  EXPECT_THROW(ConflictZones(testing::plus_junction(), params), std::invalid_argument);
}

TEST(ConflictZones, TableAJunctionsCoverTheirWholeCrossing) {
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/table_a.yaml");
  const auto& g = site.graph.graph;
  const ConflictZones zones(g);
  std::size_t branches = 0, stoppable = 0;
  for (std::size_t p = 0; p < zones.place_count(); ++p) {
    if (zones.branch(static_cast<int>(p))) ++branches;
    if (zones.stoppable(static_cast<int>(p))) ++stoppable;
  }
  EXPECT_GT(branches, 0u);
  EXPECT_GT(stoppable, zones.place_count() / 3);
  // Every place within one footprint width of a branch place conflicts with it.
  for (std::size_t b = 0; b < zones.place_count(); ++b) {
    if (!zones.branch(static_cast<int>(b))) continue;
    for (std::size_t p = 0; p < zones.place_count(); ++p) {
      if (geometry::distance(zones.position(static_cast<int>(b)), zones.position(static_cast<int>(p))) < 0.16) {
        EXPECT_TRUE(zones.conflict(static_cast<int>(b), static_cast<int>(p))) << b << " " << p;
      }
    }
  }
}

TEST(ConflictZones, ABodyReachesAMoveExactlyWhenItOverlapsOneOfTheMovesRegions) {
  // The bounding-circle rejection in body_reaches_move must never change the answer of the
  // polygon tests: bodies of several sizes on a grid around a junction, against every move.
  const map::RoadGraph g = testing::plus_junction();
  const ConflictZones zones(g);
  int reached = 0;
  int not_reached = 0;
  for (const double half : {0.05, 0.2, 0.6}) {
    for (double x = -1.5; x <= 1.5; x += 0.1) {
      for (double y = -1.5; y <= 1.5; y += 0.1) {
        const geometry::Polygon body{
            {x - half, y - half}, {x + half, y - half}, {x + half, y + half}, {x - half, y + half}};
        for (int to = 0; to < static_cast<int>(zones.place_count()); ++to) {
          for (const int from : zones.neighbours(to)) {
            bool overlaps = false;
            const auto& polygons = zones.region(0, to);
            const auto& moves = zones.region_moves(0, to);
            for (std::size_t k = 0; k < polygons.size(); ++k) {
              const bool of_move = moves[k].before < 0 || moves[k].before == from;
              overlaps = overlaps || (of_move && geometry::convex_polygons_overlap(body, polygons[k]));
            }
            ASSERT_EQ(zones.body_reaches_move(body, 0, from, to), overlaps) << x << ", " << y << " half " << half;
            (overlaps ? reached : not_reached) += 1;
          }
        }
      }
    }
  }
  EXPECT_GT(reached, 100);
  EXPECT_GT(not_reached, 100);
}

}  // namespace
}  // namespace fleet::traffic
