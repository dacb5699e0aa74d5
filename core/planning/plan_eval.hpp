#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "map/road_graph.hpp"
#include "map/site.hpp"

namespace fleet::planning {

/// Settings of one evaluation run (`fleetctl plan-eval`).
struct PlanEvalConfiguration {
  int queries = 200;
  std::uint64_t seed = 1;
  double resolution = 0.0;           ///< grid cell, metres; <= 0: road_width / 15 clamped to [0.02, 0.05]
  double obstacle_inflation = 0.15;  ///< static obstacles grow by this (the forklift's radius)
  double road_budget_ms = 100.0;
  double grid_budget_ms = 1000.0;
  double rrtconnect_budget_ms = 1000.0;
  double optimal_budget_ms = 100.0;  ///< the asymptotically optimal planner runs this long per query
  bool include_ompl = true;
};

struct PlannerStats {
  std::string name;
  int queries = 0;
  int successes = 0;
  double success = 0.0;    ///< fraction of queries with status FOUND
  double median_ms = 0.0;  ///< over all queries, failed ones included
  double p95_ms = 0.0;
  double max_ms = 0.0;
  double length_ratio = 0.0;  ///< mean over its successes of length / shortest found by any planner
  double max_length_ratio = 0.0;
};

struct PlanEvalReport {
  std::string site;
  int queries = 0;
  std::uint64_t seed = 0;
  double resolution = 0.0;
  int grid_width = 0;
  int grid_height = 0;
  std::size_t graph_points = 0;
  std::size_t query_points = 0;  ///< points the queries were drawn from (largest strong component)
  std::vector<PlannerStats> planners;

  const PlannerStats* find(const std::string& name) const;
};

/// Runs every planner on the same random start/goal pairs of a site: road-graph A* on the graph,
/// grid A*, the grassfire planner and the OMPL planners on the static grid of the same site (roads
/// and loading areas free, enabled obstacles inflated). Start and goal are graph points of the
/// graph's largest strongly connected component, so every query has an answer on the roads. Each
/// planner gets one untimed warm-up query first, and its grid is set again after it so that no
/// cached result of the warm-up is timed.
PlanEvalReport run_plan_eval(const map::Site& site, const map::RoadGraph& graph,
                             const PlanEvalConfiguration& configuration);

}  // namespace fleet::planning
