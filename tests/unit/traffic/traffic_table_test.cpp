#include <gtest/gtest.h>

#include <string>

#include "map/site_map.hpp"
#include "test_paths.hpp"
#include "traffic/traffic_sim.hpp"

namespace fleet::traffic {
namespace {

struct TableCase {
  const char* site;
  int robots;
};

class TrafficTable : public ::testing::TestWithParam<TableCase> {};

// Thirty simulated minutes of random pick-and-drop trips on a demo table: no footprint ever
// overlaps another, nobody stands still with a task for 60 s, and every robot completes trips.
TEST_P(TrafficTable, ThirtyMinutesWithoutCollisionOrDeadlock) {
  const TableCase c = GetParam();
  const auto site = map::load_site_map(fleet::test::source_dir() + "/maps/" + c.site + ".yaml");
  const TrafficConfiguration config;
  const ConflictZones zones(site.graph.graph, config.resources);
  const SimScenario scenario = site_scenario(site, zones, c.robots);
  ASSERT_EQ(static_cast<int>(scenario.start_points.size()), c.robots);
  SimParams params;
  params.seed = 7;
  params.check_invariant = true;
  TrafficSim sim(site.graph.graph, config, params, scenario.goal_points, scenario.start_points);
  const auto& report = sim.run_until(1800.0);
  EXPECT_EQ(report.collisions, 0u) << report.first_collision;
  EXPECT_EQ(report.deadlocks, 0u);
  EXPECT_EQ(report.invariant_violations, 0u) << report.first_violation;
  for (int id = 1; id <= c.robots; ++id) EXPECT_GE(sim.goals_reached(id), 4u) << "robot " << id;
  RecordProperty("trips", static_cast<int>(report.trips));
  RecordProperty("max_wait_s", static_cast<int>(report.max_wait_s));
}

INSTANTIATE_TEST_SUITE_P(DemoTables, TrafficTable,
                         ::testing::Values(TableCase{"table_a", 4}, TableCase{"table_a", 8}, TableCase{"table_a", 12},
                                           TableCase{"table_b", 8}),
                         [](const ::testing::TestParamInfo<TableCase>& param_info) {
                           return std::string(param_info.param.site) + "_" + std::to_string(param_info.param.robots);
                         });

}  // namespace
}  // namespace fleet::traffic
