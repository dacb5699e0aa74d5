#include "traffic/conflict_zones.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "map/site_map.hpp"
#include "sim/tricycle.hpp"
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

TEST(ConflictZones, TurnSweepsHoldALongBodyTurningOnTheSpotAtABend) {
  GraphBuilder b;
  b.road(0.0, 0.0, 3.0, 0.0);
  b.road(3.0, 0.0, 3.0, 3.0);
  ResourceParams params;
  params.margin = 0.0;
  params.vehicle_types = {{"reach truck", rectangle_footprint({1.6, 0.9})}};
  const int bend = ConflictZones(b.graph(), params).place_of(point_at(b.graph(), 3.0, 0.0));
  // Halfway through its turn from east to north, the body's corners reach 0.92 m from the point.
  const geometry::Polygon halfway =
      sim::polygon_in_map({3.0, 0.0, std::acos(0.0) / 2.0}, params.vehicle_types[0].footprint);
  const auto holds_halfway = [&](const ConflictZones& zones) {
    const auto& polygons = zones.region(bend);
    return std::any_of(polygons.begin(), polygons.end(), [&](const geometry::Polygon& held) {
      return std::all_of(halfway.begin(), halfway.end(), [&](geometry::Vec2 v) { return geometry::contains(held, v); });
    });
  };
  EXPECT_FALSE(holds_halfway(ConflictZones(b.graph(), params)));
  params.turn_sweeps = true;
  const ConflictZones zones(b.graph(), params);
  EXPECT_TRUE(holds_halfway(zones));
  // A place of a road passing beside the bend, clear of the body at both headings, conflicts with
  // the bend once the turn is held.
  GraphBuilder beside = b;
  beside.road(4.28, -1.0, 4.28, 1.0);
  const ConflictZones without(beside.graph(), [&] {
    ResourceParams p = params;
    p.turn_sweeps = false;
    return p;
  }());
  const ConflictZones with(beside.graph(), params);
  const int near = with.place_of(point_at(beside.graph(), 4.28, 0.6));
  const int corner = with.place_of(point_at(beside.graph(), 3.0, 0.0));
  EXPECT_FALSE(without.conflict(corner, near));
  EXPECT_TRUE(with.conflict(corner, near));
}

}  // namespace
}  // namespace fleet::traffic
