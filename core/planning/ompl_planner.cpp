#include "planning/ompl_planner.hpp"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/informedtrees/BITstar.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>
#include <ompl/geometric/planners/rrt/RRTstar.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace fleet::planning {

namespace ob = ompl::base;
namespace og = ompl::geometric;
using geometry::Vec2;

struct OmplGridPlanner::Impl {
  std::shared_ptr<ob::SE2StateSpace> space;
  ob::SpaceInformationPtr si;
  std::atomic<std::size_t> checks{0};
};

OmplGridPlanner::OmplGridPlanner(const OmplPlannerConfiguration& configuration) : configuration_(configuration) {
  if (!(configuration.check_cells > 0.0 && configuration.check_cells <= 1.0)) {
    throw std::invalid_argument("ompl planner: check_cells must be in (0, 1]");
  }
  if (configuration.range < 0.0) throw std::invalid_argument("ompl planner: range must be >= 0");
}

OmplGridPlanner::~OmplGridPlanner() = default;

std::string OmplGridPlanner::name() const {
  switch (configuration_.algorithm) {
    case OmplAlgorithm::kRrtConnect:
      return "ompl_rrtconnect";
    case OmplAlgorithm::kRrtStar:
      return "ompl_rrtstar";
    case OmplAlgorithm::kBitStar:
      return "ompl_bitstar";
  }
  return "ompl";
}

void OmplGridPlanner::set_grid(std::shared_ptr<const OccupancyGrid> grid) {
  grid_ = std::move(grid);
  impl_.reset();
  if (!grid_) return;
  auto impl = std::make_unique<Impl>();
  impl->space = std::make_shared<ob::SE2StateSpace>();
  const geometry::Bounds b = grid_->bounds();
  ob::RealVectorBounds bounds(2);
  bounds.setLow(0, b.min_x);
  bounds.setHigh(0, b.max_x);
  bounds.setLow(1, b.min_y);
  bounds.setHigh(1, b.max_y);
  impl->space->setBounds(bounds);
  // Heading is free on an inflated grid; without weight it neither lengthens paths nor steers
  // nearest-neighbour queries.
  impl->space->setSubspaceWeight(1, 0.0);
  impl->si = std::make_shared<ob::SpaceInformation>(impl->space);
  const OccupancyGrid* g = grid_.get();
  std::atomic<std::size_t>* checks = &impl->checks;
  // One cell lookup: thread-safe, since the grid is immutable while the planner holds it.
  impl->si->setStateValidityChecker([g, checks](const ob::State* state) {
    checks->fetch_add(1, std::memory_order_relaxed);
    const auto* s = state->as<ob::SE2StateSpace::StateType>();
    return !g->occupied_at({s->getX(), s->getY()});
  });
  impl->si->setStateValidityCheckingResolution(configuration_.check_cells * grid_->resolution() /
                                               impl->space->getMaximumExtent());
  impl->si->setup();
  impl_ = std::move(impl);
}

GridPath OmplGridPlanner::plan(Vec2 start, Vec2 goal, const PlanOptions& options) {
  GridPath result;
  if (!impl_ || grid_->occupied_at(start) || grid_->occupied_at(goal)) {
    result.status = PlanStatus::kInvalidStart;
    return result;
  }
  const Deadline deadline(options);
  ob::ScopedState<ob::SE2StateSpace> s(impl_->space);
  ob::ScopedState<ob::SE2StateSpace> t(impl_->space);
  s->setXY(start.x, start.y);
  s->setYaw(0.0);
  t->setXY(goal.x, goal.y);
  t->setYaw(0.0);
  auto pdef = std::make_shared<ob::ProblemDefinition>(impl_->si);
  pdef->setStartAndGoalStates(s, t);
  if (configuration_.algorithm != OmplAlgorithm::kRrtConnect) {
    pdef->setOptimizationObjective(std::make_shared<ob::PathLengthOptimizationObjective>(impl_->si));
  }
  // A fresh planner per query: a few microseconds, and no state of the last problem can leak in.
  ob::PlannerPtr planner;
  switch (configuration_.algorithm) {
    case OmplAlgorithm::kRrtConnect: {
      auto p = std::make_shared<og::RRTConnect>(impl_->si);
      if (configuration_.range > 0.0) p->setRange(configuration_.range);
      planner = p;
      break;
    }
    case OmplAlgorithm::kRrtStar: {
      auto p = std::make_shared<og::RRTstar>(impl_->si);
      if (configuration_.range > 0.0) p->setRange(configuration_.range);
      planner = p;
      break;
    }
    case OmplAlgorithm::kBitStar:
      // OMPL reserves the name "BITstar" for the r-disc variant; the default is k-nearest.
      planner = std::make_shared<og::BITstar>(impl_->si, "kBITstar");
      break;
  }
  planner->setProblemDefinition(pdef);
  planner->setup();
  impl_->checks.store(0, std::memory_order_relaxed);

  const std::size_t cap = options.node_cap;
  std::atomic<std::size_t>* checks = &impl_->checks;
  const ob::PlannerTerminationCondition ptc([&deadline, checks, cap] {
    return deadline.cancelled() || deadline.expired() || checks->load(std::memory_order_relaxed) > cap;
  });
  planner->solve(ptc);
  result.expanded = impl_->checks.load(std::memory_order_relaxed);
  if (!pdef->hasExactSolution()) {
    if (deadline.cancelled()) {
      result.status = PlanStatus::kCancelled;
    } else {
      // A sampling planner cannot prove that no path exists; running out is all it can report.
      result.status = PlanStatus::kTimeout;
    }
    return result;
  }
  auto* path = pdef->getSolutionPath()->as<og::PathGeometric>();
  if (configuration_.algorithm == OmplAlgorithm::kRrtConnect && configuration_.simplify) {
    og::PathSimplifier simplifier(impl_->si);
    const ob::PlannerTerminationCondition left([&deadline] { return deadline.cancelled() || deadline.expired(); });
    // RRTConnect's edges are long (a fifth of the extent): with few vertices, shortcuts between
    // them cannot straighten a detour. Densify first so shortcuts can start anywhere on the path.
    const double spacing = 10.0 * grid_->resolution();
    path->interpolate(static_cast<unsigned int>(std::min(2000.0, std::ceil(path->length() / spacing)) + 2));
    simplifier.simplify(*path, left, false);
  }
  result.points.reserve(path->getStateCount());
  for (std::size_t i = 0; i < path->getStateCount(); ++i) {
    const auto* st = path->getState(i)->as<ob::SE2StateSpace::StateType>();
    result.points.push_back({st->getX(), st->getY()});
  }
  result.length = path_length(result.points);
  result.status = PlanStatus::kFound;
  return result;
}

void seed_ompl(std::uint32_t seed) {
  ompl::RNG::setSeed(seed);
}

void quiet_ompl_logs() {
  ompl::msg::setLogLevel(ompl::msg::LOG_WARN);
}

}  // namespace fleet::planning
