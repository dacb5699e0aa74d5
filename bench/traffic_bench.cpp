// Traffic: cost of the manager's cycle with 12 robots on table_a, of precomputing the
// conflict zones (table_a; the plant with and without the stackers' drives through its bends), and the evaluation
// figure: trips completed in 30 simulated minutes by 1, 4, 8 and 12 robots on table_a and table_b in the core simulator
// (counters; no time is asserted). Reads maps/ from the source tree.

#include <benchmark/benchmark.h>

#include <string>

#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "traffic/traffic_settings.hpp"
#include "traffic/traffic_sim.hpp"

namespace {

using namespace fleet;

const map::SiteMap& site(const std::string& name) {
  static const map::SiteMap a = map::load_site_map(std::string(FLEET_SOURCE_DIR) + "/maps/table_a.yaml");
  static const map::SiteMap b = map::load_site_map(std::string(FLEET_SOURCE_DIR) + "/maps/table_b.yaml");
  return name == "table_a" ? a : b;
}

traffic::TrafficSim make_sim(const std::string& name, int robots, bool one_way, bool traffic, std::uint64_t seed) {
  const auto& s = site(name);
  traffic::TrafficConfiguration config;
  config.one_way = one_way;
  const traffic::ConflictZones zones(s.graph.graph, config.resources);
  const auto scenario = traffic::site_scenario(s, zones, robots);
  traffic::SimParams params;
  params.seed = seed;
  params.traffic = traffic;
  params.check_invariant = false;
  return traffic::TrafficSim(s.graph.graph, config, params, scenario.goal_points, scenario.start_points);
}

void BM_ConflictZonesTableA(benchmark::State& state) {
  const auto& g = site("table_a").graph.graph;
  for (auto _ : state) {
    traffic::ConflictZones zones(g);
    benchmark::DoNotOptimize(zones.place_count());
  }
  state.counters["places"] = static_cast<double>(traffic::ConflictZones(g).place_count());
}
BENCHMARK(BM_ConflictZonesTableA)->Unit(benchmark::kMillisecond);

// The plant's zones for its four fleets, without (0) and with (1) the stackers' drives through
// every bend (what the server's traffic manager builds at start and at every map switch).
void BM_ConflictZonesPlant(benchmark::State& state) {
  static const map::SiteMap plant = map::load_site_map(std::string(FLEET_SOURCE_DIR) + "/maps/plant.yaml");
  traffic::ResourceParams resources =
      traffic::configuration_from(config::load_fleet_config(std::string(FLEET_SOURCE_DIR) + "/config/sites/plant.yaml"))
          .resources;
  if (state.range(0) == 0) {
    for (auto& type : resources.vehicle_types) type.drive = nullptr;
  }
  for (auto _ : state) {
    traffic::ConflictZones zones(plant.graph.graph, resources);
    benchmark::DoNotOptimize(zones.place_count());
  }
}
BENCHMARK(BM_ConflictZonesPlant)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// One TrafficManager::update with 12 robots mid-run on table_a (2 simulated minutes in, so routes,
// grants, waits and reservations are realistic). Progress is not reported between calls, so
// every call does the full cycle on the same state.
void BM_ManagerUpdate12(benchmark::State& state) {
  auto sim = make_sim("table_a", 12, true, true, 3);
  sim.run_until(120.0);
  double now = sim.time();
  for (auto _ : state) {
    now += 1e-6;
    auto result = sim.manager().update(now);
    benchmark::DoNotOptimize(result.grants.data());
  }
}
BENCHMARK(BM_ManagerUpdate12)->Unit(benchmark::kMicrosecond);

// One simulator step (motion, progress reports, manager update, collision check) with 12 robots.
void BM_SimStep12(benchmark::State& state) {
  auto sim = make_sim("table_a", 12, true, true, 3);
  sim.run_until(120.0);
  for (auto _ : state) sim.step();
}
BENCHMARK(BM_SimStep12)->Unit(benchmark::kMicrosecond);

// The evaluation figure: 30 simulated minutes of random pick-and-drop trips.
// Args: robots, site (0 = table_a, 1 = table_b), mode (0 = one-way traffic control, 1 = traffic
// control with every road both ways, 2 = no traffic control: robots drive through each other).
void BM_Trips(benchmark::State& state) {
  const int robots = static_cast<int>(state.range(0));
  const std::string name = state.range(1) == 0 ? "table_a" : "table_b";
  const int mode = static_cast<int>(state.range(2));
  traffic::SimReport report;
  for (auto _ : state) {
    auto sim = make_sim(name, robots, mode == 0, mode != 2, 1);
    report = sim.run_until(1800.0);
  }
  state.counters["trips"] = static_cast<double>(report.trips);
  state.counters["mean_trip_s"] = report.mean_trip_s;
  state.counters["max_wait_s"] = report.max_wait_s;
  state.counters["collisions"] = static_cast<double>(report.collisions);
  state.counters["deadlocks"] = static_cast<double>(report.deadlocks);
  state.counters["sidings"] = static_cast<double>(report.sidings);
  state.counters["reroutes"] = static_cast<double>(report.reroutes);
}
BENCHMARK(BM_Trips)
    ->ArgNames({"robots", "site", "mode"})
    ->ArgsProduct({{1, 4, 8, 12}, {0, 1}, {0}})
    ->ArgsProduct({{1, 4, 8, 12}, {0}, {1, 2}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
