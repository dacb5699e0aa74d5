#include "planning/occupancy_grid.hpp"

#include <gtest/gtest.h>

#include "planning/static_grid.hpp"
#include "test_graphs.hpp"

namespace fleet::planning {
namespace {

using testing::square;

TEST(OccupancyGrid, CellGeometry) {
  OccupancyGrid g({0.0, 0.0, 3.0, 3.0}, 0.02);
  EXPECT_EQ(g.width(), 150);
  EXPECT_EQ(g.height(), 150);
  EXPECT_EQ(g.cell_of({0.01, 0.03}), (CellIndex{0, 1}));
  EXPECT_NEAR(g.cell_center(2, 3).x, 0.05, 1e-12);
  EXPECT_TRUE(g.occupied(-1, 0));
  EXPECT_TRUE(g.occupied(0, 150));
  EXPECT_FALSE(g.occupied(0, 0));
  EXPECT_THROW(OccupancyGrid({0, 0, 1, 1}, 0.0), std::invalid_argument);
}

TEST(OccupancyGrid, PolygonFillCoversCentresAndThinObstacles) {
  OccupancyGrid g({0.0, 0.0, 1.0, 1.0}, 0.1);
  g.fill_polygon(square(0.5, 0.5, 0.4), true);
  // Centres 0.35, 0.45, 0.55, 0.65 inside: 4 x 4 cells, plus the boundary cells the edges cross.
  for (int y = 3; y <= 6; ++y)
    for (int x = 3; x <= 6; ++x) EXPECT_TRUE(g.occupied(x, y));
  EXPECT_FALSE(g.occupied(1, 1));
  // A sliver thinner than a cell still marks the cells it lies in.
  OccupancyGrid h({0.0, 0.0, 1.0, 1.0}, 0.1);
  h.fill_polygon({{0.21, 0.21}, {0.79, 0.21}, {0.79, 0.22}, {0.21, 0.22}}, true);
  EXPECT_TRUE(h.occupied(2, 2));
  EXPECT_TRUE(h.occupied(7, 2));
  EXPECT_FALSE(h.occupied(5, 3));
}

TEST(OccupancyGrid, SegmentFreeSeesEveryCellOnTheWay) {
  OccupancyGrid g({0.0, 0.0, 1.0, 1.0}, 0.1);
  g.set(5, 5, true);
  EXPECT_FALSE(g.segment_free({0.05, 0.05}, {0.95, 0.95}));
  EXPECT_TRUE(g.segment_free({0.05, 0.15}, {0.95, 0.15}));
  EXPECT_FALSE(g.segment_free({0.55, 0.05}, {0.55, 0.95}));
  // Squeezing diagonally between two cells that touch at a corner is refused.
  OccupancyGrid d({0.0, 0.0, 1.0, 1.0}, 0.1);
  d.set(3, 4, true);
  d.set(4, 3, true);
  EXPECT_FALSE(d.segment_free({0.35, 0.35}, {0.45, 0.45}));
  // Leaving the grid is never free.
  EXPECT_FALSE(g.segment_free({0.5, 0.5}, {1.5, 0.5}));
}

TEST(OccupancyGrid, DilationGrowsByRadius) {
  OccupancyGrid g({0.0, 0.0, 2.0, 2.0}, 0.1);
  g.set(10, 10, true);
  const OccupancyGrid d = g.dilated(0.3);
  EXPECT_TRUE(d.occupied(13, 10));
  EXPECT_TRUE(d.occupied(10, 7));
  EXPECT_TRUE(d.occupied(12, 12));  // sqrt(8) cells < 3
  EXPECT_FALSE(d.occupied(14, 10));
  EXPECT_FALSE(d.occupied(13, 13));  // sqrt(18) > 3
  EXPECT_EQ(g.occupied_count(), 1u);
}

TEST(OccupancyGrid, DilationInPlaceGrowsOnlyTheCellsOccupiedBeforeIt) {
  // A wall of cells across whole rows of eight (the free-row skip) and one lone cell: grown in
  // place, the grown cells must not grow in turn.
  OccupancyGrid g({0.0, 0.0, 3.2, 2.0}, 0.1);
  for (int x = 0; x < 32; ++x) g.set(x, 5, true);
  g.set(20, 15, true);
  OccupancyGrid in_place = g;
  in_place.dilate(0.2);
  const OccupancyGrid copy = g.dilated(0.2);
  EXPECT_TRUE(in_place.occupied(3, 7));
  EXPECT_FALSE(in_place.occupied(3, 8));
  EXPECT_TRUE(in_place.occupied(20, 17));
  EXPECT_FALSE(in_place.occupied(20, 18));
  for (int y = 0; y < g.height(); ++y) {
    for (int x = 0; x < g.width(); ++x) EXPECT_EQ(in_place.occupied(x, y), copy.occupied(x, y)) << x << ", " << y;
  }
}

TEST(OccupancyGrid, UnionOfTwoGridsIsOccupiedWhereEitherIs) {
  OccupancyGrid a({0.0, 0.0, 1.0, 1.0}, 0.1);
  OccupancyGrid b = a;
  a.set(1, 1, true);
  b.set(8, 8, true);
  OccupancyGrid out;
  out.assign_union(a, b);
  EXPECT_TRUE(out.same_geometry(a));
  EXPECT_TRUE(out.occupied(1, 1));
  EXPECT_TRUE(out.occupied(8, 8));
  EXPECT_EQ(out.occupied_count(), 2u);
  b.set(8, 8, false);
  out.assign_union(a, b);  // into the storage it has
  EXPECT_EQ(out.occupied_count(), 1u);
  EXPECT_THROW(out.assign_union(a, OccupancyGrid({0.0, 0.0, 2.0, 1.0}, 0.1)), std::invalid_argument);
}

TEST(StaticGrid, RoadSquaresLoadingAreasAndObstacles) {
  const map::RoadGraph graph = testing::lattice_graph(2, 1, 1.0, 0.1);  // (0.3,0.3)-(1.3,0.3)
  map::Site site = testing::site_for(graph);
  site.bounds = {0.0, 0.0, 1.6, 1.0};
  map::LoadingArea area;
  area.id = "A1";
  area.pose = {0.8, 0.8, -1.5707963};
  site.loading_areas.push_back(area);
  map::StaticObstacle o;
  o.id = "O1";
  o.polygon = square(1.1, 0.3, 0.1);
  site.static_obstacles.push_back(o);
  StaticGrid sg({.resolution = 0.02, .obstacle_inflation = 0.05}, site, graph);
  const OccupancyGrid& g = sg.grid();
  EXPECT_FALSE(g.occupied_at({0.8, 0.3}));   // road
  EXPECT_FALSE(g.occupied_at({0.8, 0.43}));  // inside the 30 cm road square
  EXPECT_TRUE(g.occupied_at({0.5, 0.6}));    // off the road
  EXPECT_FALSE(g.occupied_at({0.8, 0.8}));   // loading area
  EXPECT_FALSE(g.occupied_at({0.8, 0.6}));   // corridor to the road
  EXPECT_FALSE(g.occupied_at({1.1, 0.3}));   // obstacle disabled at start
  ASSERT_TRUE(sg.set_obstacle_enabled("O1", true));
  EXPECT_FALSE(sg.set_obstacle_enabled("nope", true));
  EXPECT_TRUE(sg.grid().occupied_at({1.1, 0.3}));
  EXPECT_TRUE(sg.grid().occupied_at({1.19, 0.3}));  // inflated by 5 cm
  EXPECT_FALSE(sg.grid().occupied_at({1.23, 0.3}));
  sg.add_temporary("t", square(0.5, 0.3, 0.1));
  EXPECT_TRUE(sg.grid().occupied_at({0.5, 0.3}));
  EXPECT_FALSE(sg.permanent_grid().occupied_at({0.5, 0.3}));
  EXPECT_TRUE(sg.remove_temporary("t"));
  EXPECT_FALSE(sg.grid().occupied_at({0.5, 0.3}));
}

TEST(StaticGrid, RebuildsOnlyOnChange) {
  const map::RoadGraph graph = testing::lattice_graph(2, 1, 1.0, 0.1);
  StaticGrid sg({.resolution = 0.02}, testing::site_for(graph), graph);
  sg.grid();
  sg.permanent_grid();
  sg.grid();
  EXPECT_EQ(sg.build_count(), 1u);
  const auto rev = sg.revision();
  EXPECT_FALSE(sg.remove_temporary("absent"));
  EXPECT_EQ(sg.revision(), rev);
  sg.add_temporary("t", square(0.5, 0.3, 0.1));
  sg.grid();
  sg.grid();
  EXPECT_EQ(sg.build_count(), 2u);
}

}  // namespace
}  // namespace fleet::planning
