#include "planning/plan_eval.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

#include "common/percentile.hpp"
#include "map/road_graph_builder.hpp"
#include "planning/grassfire_planner.hpp"
#include "planning/grid_astar.hpp"
#include "planning/ompl_planner.hpp"
#include "planning/road_planner.hpp"
#include "planning/static_grid.hpp"

namespace fleet::planning {

using geometry::Vec2;

namespace {

struct Outcome {
  double ms = 0.0;
  bool found = false;
  double length = 0.0;
};

PlanOptions budget(double ms) {
  PlanOptions o;
  o.time_budget = std::chrono::microseconds(static_cast<std::int64_t>(ms * 1000.0));
  return o;
}

double elapsed_ms(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

const PlannerStats* PlanEvalReport::find(const std::string& name) const {
  for (const auto& p : planners) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

PlanEvalReport run_plan_eval(const map::Site& site, const map::RoadGraph& graph, const PlanEvalConfiguration& c) {
  if (c.queries <= 0) throw std::invalid_argument("plan-eval: queries must be positive");
  if (graph.points.size() < 2)
    throw std::invalid_argument("plan-eval: site '" + site.name + "' has fewer than two graph points");
  PlanEvalReport report;
  report.site = site.name;
  report.queries = c.queries;
  report.seed = c.seed;
  report.graph_points = graph.points.size();
  report.resolution = c.resolution > 0.0 ? c.resolution : std::clamp(site.road_width / 15.0, 0.02, 0.05);

  StaticGrid static_grid({.resolution = report.resolution, .obstacle_inflation = c.obstacle_inflation}, site, graph);
  auto grid = std::make_shared<const OccupancyGrid>(static_grid.grid());
  report.grid_width = grid->width();
  report.grid_height = grid->height();

  // Queries: pairs of distinct points of the largest strongly connected component.
  std::vector<int> component;
  const std::size_t components = map::strong_components(graph, component);
  std::vector<std::size_t> sizes(components, 0);
  for (int k : component) ++sizes[static_cast<std::size_t>(k)];
  const int main = static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  std::vector<int> pool;
  for (std::size_t i = 0; i < graph.points.size(); ++i) {
    if (component[i] == main) pool.push_back(static_cast<int>(i));
  }
  report.query_points = pool.size();
  if (pool.size() < 2) throw std::invalid_argument("plan-eval: no two mutually reachable graph points");
  std::mt19937_64 rng(c.seed);
  std::uniform_int_distribution<std::size_t> pick(0, pool.size() - 1);
  std::vector<std::pair<Vec2, Vec2>> queries;
  while (static_cast<int>(queries.size()) < c.queries) {
    const int a = pool[pick(rng)];
    const int b = pool[pick(rng)];
    if (a == b) continue;
    queries.push_back({{graph.points[a].x, graph.points[a].y}, {graph.points[b].x, graph.points[b].y}});
  }

  std::vector<std::string> names;
  std::vector<std::vector<Outcome>> outcomes;

  // Road-graph A*.
  {
    RoadPlanner road(graph);
    road.set_obstacles(*grid);
    auto run = [&](const std::pair<Vec2, Vec2>& q) {
      Outcome o;
      const auto t0 = std::chrono::steady_clock::now();
      const RoadPlan p =
          road.plan({q.first.x, q.first.y, 0.0}, {q.second.x, q.second.y, 0.0}, budget(c.road_budget_ms));
      o.ms = elapsed_ms(t0);
      o.found = p.status == PlanStatus::kFound;
      o.length = p.length;
      return o;
    };
    run(queries.front());
    names.push_back("road_astar");
    outcomes.emplace_back();
    for (const auto& q : queries) outcomes.back().push_back(run(q));
  }

  // Grid planners.
  std::vector<std::pair<std::unique_ptr<GridPlanner>, double>> grid_planners;
  grid_planners.emplace_back(std::make_unique<GridAStar>(), c.grid_budget_ms);
  grid_planners.emplace_back(std::make_unique<GrassfirePlanner>(), c.grid_budget_ms);
  if (c.include_ompl) {
    seed_ompl(static_cast<std::uint32_t>(c.seed) + 1u);  // OMPL reads 0 as "pick a random seed"
    quiet_ompl_logs();
    grid_planners.emplace_back(
        std::make_unique<OmplGridPlanner>(OmplPlannerConfiguration{.algorithm = OmplAlgorithm::kRrtConnect}),
        c.rrtconnect_budget_ms);
    grid_planners.emplace_back(
        std::make_unique<OmplGridPlanner>(OmplPlannerConfiguration{.algorithm = OmplAlgorithm::kBitStar}),
        c.optimal_budget_ms);
  }
  for (auto& [planner, ms] : grid_planners) {
    planner->set_grid(grid);
    const double b = ms;
    GridPlanner* p = planner.get();
    auto run = [&](const std::pair<Vec2, Vec2>& q) {
      Outcome o;
      const auto t0 = std::chrono::steady_clock::now();
      const GridPath path = p->plan(q.first, q.second, budget(b));
      o.ms = elapsed_ms(t0);
      o.found = path.status == PlanStatus::kFound;
      o.length = path.length;
      return o;
    };
    run(queries.front());
    // The warm-up must leave no answer behind: the grassfire planner keeps its last goal's
    // transform, which would make the first timed query (the same one) free.
    planner->set_grid(grid);
    names.push_back(p->name());
    outcomes.emplace_back();
    for (const auto& q : queries) outcomes.back().push_back(run(q));
  }

  // Shortest length any planner found, per query.
  std::vector<double> best(queries.size(), std::numeric_limits<double>::infinity());
  for (const auto& per : outcomes) {
    for (std::size_t i = 0; i < per.size(); ++i) {
      if (per[i].found) best[i] = std::min(best[i], per[i].length);
    }
  }
  for (std::size_t k = 0; k < names.size(); ++k) {
    PlannerStats s;
    s.name = names[k];
    s.queries = static_cast<int>(queries.size());
    std::vector<double> times;
    double ratio_sum = 0.0;
    for (std::size_t i = 0; i < outcomes[k].size(); ++i) {
      const Outcome& o = outcomes[k][i];
      times.push_back(o.ms);
      if (!o.found) continue;
      ++s.successes;
      const double r = best[i] > 1e-12 ? o.length / best[i] : 1.0;
      ratio_sum += r;
      s.max_length_ratio = std::max(s.max_length_ratio, r);
    }
    s.success = static_cast<double>(s.successes) / s.queries;
    s.median_ms = common::percentile(times, 0.5);
    s.p95_ms = common::percentile(times, 0.95);
    s.max_ms = common::percentile(times, 1.0);
    s.length_ratio = s.successes > 0 ? ratio_sum / s.successes : 0.0;
    report.planners.push_back(s);
  }
  return report;
}

}  // namespace fleet::planning
