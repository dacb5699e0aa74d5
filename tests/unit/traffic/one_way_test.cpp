#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "map/site_map.hpp"
#include "test_graphs.hpp"
#include "traffic/one_way.hpp"
#include "traffic/route_search.hpp"

namespace fleet::traffic {
namespace {

TEST(OneWay, DemoTablesStayStronglyConnectedWithOneWayCorridors) {
  for (const char* name : {"table_a", "table_b"}) {
    const auto site = map::load_site_map(std::string(FLEET_SOURCE_DIR) + "/maps/" + name + ".yaml");
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
      goals.push_back(map::nearest_point(g, area.pose.x + 0.3 * std::cos(area.pose.yaw), area.pose.y + 0.3 * std::sin(area.pose.yaw)));
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

TEST(OneWay, RoutesOnAGridOfRoadsStayCloseToTheirTwoWayLength) {
  // The big warehouse's 24 x 11 roads: a depth-first orientation alone sent carts around the site
  // for places a few blocks apart.
  const auto site = map::load_site_map(std::string(FLEET_SOURCE_DIR) + "/maps/big_warehouse.yaml");
  const auto& g = site.graph.graph;
  const ConflictZones zones(g);
  const OneWayPlan plan = one_way_plan(g, zones);
  RouteSearch one_way(plan.graph, zones);
  RouteSearch two_way(g, zones);
  const auto length = [&](const std::vector<int>& route) {
    double sum = 0.0;
    for (std::size_t k = 1; k < route.size(); ++k) {
      sum += std::hypot(
          g.points[static_cast<std::size_t>(route[k])].x - g.points[static_cast<std::size_t>(route[k - 1])].x,
          g.points[static_cast<std::size_t>(route[k])].y - g.points[static_cast<std::size_t>(route[k - 1])].y);
    }
    return sum;
  };
  double one_way_sum = 0.0, two_way_sum = 0.0, worst = 0.0;
  const auto& areas = site.site.loading_areas;
  for (std::size_t i = 0; i < areas.size(); i += 97) {
    for (std::size_t j = 13; j < areas.size(); j += 101) {
      const int a = map::nearest_point(g, areas[i].pose.x, areas[i].pose.y);
      const int b = map::nearest_point(g, areas[j].pose.x, areas[j].pose.y);
      if (a == b) continue;
      const double d1 = length(one_way.shortest(a, b));
      const double d2 = length(two_way.shortest(a, b));
      ASSERT_GT(d1, 0.0) << a << " -> " << b;
      one_way_sum += d1;
      two_way_sum += d2;
      worst = std::max(worst, d1 - d2);
    }
  }
  EXPECT_LT(one_way_sum, 1.5 * two_way_sum);
  EXPECT_LT(worst, 300.0) << "metres longer than on two-way roads, at worst";
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
