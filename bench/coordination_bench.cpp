// Coordination core on the big warehouse (200 m x 100 m, 14 558 graph points): the driving
// distance from a place to a goal no robot had before, which PlacePibt asks for whenever a robot
// is given a new goal, and then from the place's neighbours (its candidate moves); and the plan
// steps of 500 robots on random trips there in the core simulator. No time is asserted. Reads
// maps/ from the source tree.

#include <benchmark/benchmark.h>

#include <string>

#include "coordination/place_graph.hpp"
#include "coordination/place_sim.hpp"
#include "map/site_map.hpp"
#include "traffic/conflict_zones.hpp"
#include "traffic/traffic_sim.hpp"

namespace {

using namespace fleet;

const map::SiteMap& big_warehouse() {
  static const map::SiteMap site = map::load_site_map(std::string(FLEET_SOURCE_DIR) + "/maps/big_warehouse.yaml");
  return site;
}

void BM_PlaceDistancesToNewGoal(benchmark::State& state) {
  const auto& graph = big_warehouse().graph.graph;
  const traffic::ConflictZones zones(graph);
  coordination::PlaceGraph places(graph, zones);
  const int count = places.place_count();
  int goal = 0;
  int from = 0;
  for (auto _ : state) {
    // A pair not asked for before, spread over the site.
    goal = (goal + 7919) % count;
    from = (from + 4099) % count;
    benchmark::DoNotOptimize(places.distance(0, from, goal));
    for (const int next : places.successors(0, from)) benchmark::DoNotOptimize(places.distance(0, next, goal));
  }
  state.counters["places"] = static_cast<double>(count);
  state.counters["settled_per_goal"] =
      static_cast<double>(places.places_settled()) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PlaceDistancesToNewGoal)->Iterations(200)->Unit(benchmark::kMillisecond);

// 500 robots on random trips between the loading areas, planned every step: the mean and the
// longest plan step over two simulated minutes (counters).
void BM_PlaceSim500(benchmark::State& state) {
  const auto& site = big_warehouse();
  const traffic::ConflictZones zones(site.graph.graph);
  const auto scenario = traffic::site_scenario(site, zones, 500, site.site.approach_distance);
  coordination::PlaceSimParams params;
  params.speed = 1.0;
  params.dwell = 5.0;
  coordination::PlaceSimReport report;
  for (auto _ : state) {
    coordination::PlaceSim sim(site.graph.graph, zones, params, scenario.goal_points, scenario.start_points);
    report = sim.run_until(120.0);
  }
  state.counters["plan_steps"] = static_cast<double>(report.plan_steps);
  state.counters["plan_ms_mean"] = report.planning_ms_mean;
  state.counters["plan_ms_max"] = report.planning_ms_max;
  state.counters["trips"] = static_cast<double>(report.trips);
}
BENCHMARK(BM_PlaceSim500)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
