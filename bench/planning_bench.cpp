// Planning micro-benchmarks. Targets, read from the output, never asserted:
//   road A* on table_a median <= 0.1 ms; grid A* on the warehouse at 5 cm median <= 3 ms;
//   one 360-beam 4 m lidar scan into OctoMap at 2 cm <= 1 ms.
// Sites come from maps/; FLEET_SOURCE_DIR is the project root.

#include <benchmark/benchmark.h>
#include <octomap/OcTree.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "map/road_graph_builder.hpp"
#include "map/site_map.hpp"
#include "planning/dynamic_grid.hpp"
#include "planning/grid_astar.hpp"
#include "planning/lidar_sim.hpp"
#include "planning/octomap_layer.hpp"
#include "planning/ompl_planner.hpp"
#include "planning/road_planner.hpp"
#include "planning/static_grid.hpp"

namespace {

using namespace fleet;
using geometry::Vec2;

const map::SiteMap& site(const std::string& name) {
  static std::map<std::string, map::SiteMap> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    it =
        cache.emplace(name, map::load_site_map_unchecked(map::site_path(std::string(FLEET_SOURCE_DIR) + "/maps", name)))
            .first;
  }
  return it->second;
}

/// Random pairs of graph points, the same for every run.
std::vector<std::pair<Vec2, Vec2>> queries(const map::RoadGraph& g, int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> pick(0, g.points.size() - 1);
  std::vector<std::pair<Vec2, Vec2>> out;
  while (static_cast<int>(out.size()) < n) {
    const auto& a = g.points[pick(rng)];
    const auto& b = g.points[pick(rng)];
    if (a.id != b.id) out.push_back({{a.x, a.y}, {b.x, b.y}});
  }
  return out;
}

std::shared_ptr<const planning::OccupancyGrid> static_grid(const map::SiteMap& s, double resolution) {
  planning::StaticGrid sg({.resolution = resolution, .obstacle_inflation = 0.15}, s.site, s.graph.graph);
  return std::make_shared<const planning::OccupancyGrid>(sg.grid());
}

void BM_RoadAStar(benchmark::State& state, const std::string& name) {
  const auto& s = site(name);
  planning::RoadPlanner planner(s.graph.graph);
  const auto qs = queries(s.graph.graph, 256, 1);
  std::size_t i = 0;
  for (auto _ : state) {
    const auto& q = qs[i++ % qs.size()];
    auto plan = planner.plan({q.first.x, q.first.y, 0.0}, {q.second.x, q.second.y, 0.0});
    benchmark::DoNotOptimize(plan);
  }
  state.counters["points"] = static_cast<double>(s.graph.graph.points.size());
}
BENCHMARK_CAPTURE(BM_RoadAStar, table_a, std::string("table_a"));
BENCHMARK_CAPTURE(BM_RoadAStar, warehouse, std::string("warehouse"));

void BM_GridPlanner(benchmark::State& state, const std::string& name, int kind) {
  const auto& s = site(name);
  const auto grid = static_grid(s, name == "warehouse" ? 0.05 : 0.02);
  std::unique_ptr<planning::GridPlanner> planner;
  if (kind == 0) planner = std::make_unique<planning::GridAStar>();
  if (kind == 1)
    planner =
        std::make_unique<planning::GridAStar>(planning::GridAStarConfiguration{.jump_points = false, .smooth = false});
  if (kind == 2) {
    // OMPL's generator is process-wide and takes a seed only before its first draw.
    static const bool seeded = [] {
      planning::quiet_ompl_logs();
      planning::seed_ompl(1);
      return true;
    }();
    (void)seeded;
    planner = std::make_unique<planning::OmplGridPlanner>();
  }
  planner->set_grid(grid);
  const auto qs = queries(s.graph.graph, 256, 1);
  std::size_t i = 0;
  int found = 0;
  for (auto _ : state) {
    const auto& q = qs[i++ % qs.size()];
    const auto path = planner->plan(q.first, q.second, {});
    found += path.status == planning::PlanStatus::kFound;
    benchmark::DoNotOptimize(path);
  }
  state.counters["cells"] = static_cast<double>(grid->size());
  state.counters["success"] = static_cast<double>(found) / static_cast<double>(state.iterations());
}
// Jump point search + smoothing (the planner plan-eval reports as grid_astar).
BENCHMARK_CAPTURE(BM_GridPlanner, jps_warehouse, std::string("warehouse"), 0)->Unit(benchmark::kMillisecond);
// Textbook binary-heap A* on the same grid and queries: the baseline to beat.
BENCHMARK_CAPTURE(BM_GridPlanner, plain_astar_warehouse, std::string("warehouse"), 1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GridPlanner, rrtconnect_warehouse, std::string("warehouse"), 2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GridPlanner, jps_table_a, std::string("table_a"), 0)->Unit(benchmark::kMicrosecond);

/// A robot driving along the warehouse's main aisle among three others and an obstacle.
struct ScanScene {
  std::vector<geometry::Polygon> polygons;
  planning::LidarSim lidar;
  std::vector<planning::LidarScan> scans;

  ScanScene() {
    polygons.push_back({{10, 3.7}, {11, 3.7}, {11, 4.7}, {10, 4.7}});
    for (double x : {6.0, 9.0, 14.0}) polygons.push_back(geometry::footprint_polygon({x, 4.2, 0.3}, {1.2, 0.8}));
    for (int k = 0; k < 64; ++k) scans.push_back(lidar.scan({4.0 + 0.05 * k, 4.2, 0.0}, polygons));
  }
};

planning::OctoMapConfiguration warehouse_octomap() {
  planning::OctoMapConfiguration c;
  c.resolution = 0.02;
  c.area = {0.0, 0.0, 40.0, 20.0};
  c.projection_resolution = 0.05;
  return c;
}

// Steady state: the robot keeps scanning while it drives; the tree already holds the area.
void BM_LidarScanIntoOctoMap(benchmark::State& state) {
  static const ScanScene scene;
  planning::OctoMapLayer layer(warehouse_octomap());
  for (const auto& s : scene.scans) layer.insert_scan(s);
  std::size_t i = 0;
  for (auto _ : state) layer.insert_scan(scene.scans[i++ % scene.scans.size()]);
  state.counters["leaves"] = static_cast<double>(layer.leaf_count());
}
BENCHMARK(BM_LidarScanIntoOctoMap)->Unit(benchmark::kMicrosecond);

// The first scan into an empty tree: every leaf is created.
void BM_LidarFirstScanIntoOctoMap(benchmark::State& state) {
  static const ScanScene scene;
  for (auto _ : state) {
    state.PauseTiming();
    auto layer = std::make_unique<planning::OctoMapLayer>(warehouse_octomap());
    state.ResumeTiming();
    layer->insert_scan(scene.scans[0]);
    state.PauseTiming();
    layer.reset();
    state.ResumeTiming();
  }
}
BENCHMARK(BM_LidarFirstScanIntoOctoMap)->Unit(benchmark::kMicrosecond);

// Reference: the same scans through OctoMap's own insertPointCloud (max range, no lazy eval).
void BM_OctoMapInsertPointCloud(benchmark::State& state) {
  static const ScanScene scene;
  octomap::OcTree tree(0.02);
  std::vector<octomap::Pointcloud> clouds;
  for (const auto& s : scene.scans) {
    octomap::Pointcloud cloud;
    for (std::size_t b = 0; b < s.ranges.size(); ++b) {
      const double a = s.pose.yaw + s.angle_min + static_cast<double>(b) * s.angle_increment;
      // No return: a point just beyond max range, which insertPointCloud clears up to max range.
      const double r = std::isfinite(s.ranges[b]) ? s.ranges[b] : s.max_range + 0.1;
      cloud.push_back(static_cast<float>(s.pose.x + r * std::cos(a)), static_cast<float>(s.pose.y + r * std::sin(a)),
                      0.1f);
    }
    clouds.push_back(std::move(cloud));
  }
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    const auto& p = scene.scans[k].pose;
    tree.insertPointCloud(clouds[k], octomap::point3d(static_cast<float>(p.x), static_cast<float>(p.y), 0.1f), 4.0);
  }
  std::size_t i = 0;
  for (auto _ : state) {
    const std::size_t k = i++ % clouds.size();
    const auto& p = scene.scans[k].pose;
    tree.insertPointCloud(clouds[k], octomap::point3d(static_cast<float>(p.x), static_cast<float>(p.y), 0.1f), 4.0);
  }
}
BENCHMARK(BM_OctoMapInsertPointCloud)->Unit(benchmark::kMicrosecond);

void BM_LidarSimScan(benchmark::State& state) {
  static const ScanScene scene;
  for (auto _ : state) benchmark::DoNotOptimize(scene.lidar.scan({5.0, 4.2, 0.1}, scene.polygons));
}
BENCHMARK(BM_LidarSimScan)->Unit(benchmark::kMicrosecond);

void BM_StaticGridRebuild(benchmark::State& state) {
  const auto& s = site("warehouse");
  planning::StaticGrid sg({.resolution = 0.05, .obstacle_inflation = 0.15}, s.site, s.graph.graph);
  bool on = false;
  for (auto _ : state) {
    on = !on;
    sg.set_obstacle_enabled("O1", on);
    benchmark::DoNotOptimize(sg.grid());
  }
}
BENCHMARK(BM_StaticGridRebuild)->Unit(benchmark::kMillisecond);

void BM_DynamicGridUpdate(benchmark::State& state, const std::string& name) {
  const auto& s = site(name);
  const double res = name == "warehouse" ? 0.05 : 0.02;
  planning::StaticGrid sg({.resolution = res}, s.site, s.graph.graph);
  planning::DynamicGrid dyn;
  std::vector<planning::Neighbour> others;
  for (int k = 0; k < 3; ++k) {
    planning::Neighbour n;
    n.id = {'r', static_cast<char>('0' + k)};
    const auto& p = s.graph.graph.points[static_cast<std::size_t>(k * 37) % s.graph.graph.points.size()];
    n.pose = {p.x, p.y, 0.0};
    n.speed = 0.2;
    n.age = 0.1 * k;
    others.push_back(n);
  }
  planning::OccupancyGrid sensed(sg.grid().bounds(), res);
  for (auto _ : state) {
    dyn.update(sg.permanent_grid(), others, &sensed);
    benchmark::DoNotOptimize(dyn.grid());
  }
}
BENCHMARK_CAPTURE(BM_DynamicGridUpdate, table_a, std::string("table_a"))->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_DynamicGridUpdate, warehouse, std::string("warehouse"))->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
