#include "traffic/one_way.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "map/site_map.hpp"
#include "test_graphs.hpp"
#include "test_paths.hpp"
#include "traffic/route_search.hpp"

namespace fleet::traffic {
namespace {

TEST(OneWay, DemoTablesStayStronglyConnectedWithOneWayCorridors) {
  for (const char* name : {"table_a", "table_b"}) {
    const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/" + name + ".yaml");
    const auto& g = site.graph.graph;
    const ConflictZones zones(g);
    const OneWayPlan plan = one_way_plan(g, zones);
    std::size_t one_way = 0;
    for (int d : plan.corridor_direction) one_way += d != 0 ? 1 : 0;
    EXPECT_GE(one_way, 6u) << name;
    EXPECT_LT(plan.graph.edge_count(), g.edge_count()) << name;
    // Every loading area's approach point reaches every other one.
    RouteSearch search(plan.graph, zones);
    std::vector<int> goals;
    for (const auto& area : site.site.loading_areas) {
      goals.push_back(map::nearest_point(g, area.pose.x + 0.3 * std::cos(area.pose.yaw),
                                         area.pose.y + 0.3 * std::sin(area.pose.yaw)));
    }
    for (int a : goals) {
      for (int b : goals) {
        if (a != b) {
          EXPECT_FALSE(search.shortest(a, b).empty()) << name << " " << a << " -> " << b;
        }
      }
    }
    // Inside a one-way corridor only the corridor's direction is left.
    for (std::size_t i = 0; i < plan.graph.points.size(); ++i) {
      const int pa = zones.place_of(static_cast<int>(i));
      for (int j : plan.graph.successors[i]) {
        const int pb = zones.place_of(j);
        const int c = zones.corridor(pa);
        if (c < 0 || c != zones.corridor(pb) || pa == pb) continue;
        const int o = plan.corridor_direction[static_cast<std::size_t>(c)];
        if (o != 0) {
          EXPECT_EQ(zones.corridor_direction(pa, pb), o);
        }
      }
    }
  }
}

TEST(OneWay, DeadEndsAndTreesStayTwoWay) {
  const auto g = testing::corridor_with_siding();
  const ConflictZones zones(g);
  const OneWayPlan plan = one_way_plan(g, zones);
  for (int d : plan.corridor_direction) EXPECT_EQ(d, 0);
  EXPECT_EQ(plan.graph.edge_count(), g.edge_count());
}

}  // namespace
}  // namespace fleet::traffic
