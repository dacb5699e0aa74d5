#include "robot/navigation.hpp"

#include <limits>

namespace fleet::robot {

namespace {

planning::StaticGrid make_static_grid(double resolution, const map::SiteMap& site) {
  return planning::StaticGrid({.resolution = resolution}, site.site, site.graph.graph);
}

}  // namespace

Navigation::Navigation(NavigationParams params, std::shared_ptr<const map::SiteMap> site,
                       const geometry::Footprint& footprint)
    : params_(std::move(params)),
      site_(std::move(site)),
      static_grid_(make_static_grid(params_.grid_resolution, *site_)),
      road_(params_.route_graph ? *params_.route_graph : site_->graph.graph),
      routes_(road_, grid_astar_, params_.routes),
      grid_revision_(std::numeric_limits<std::uint64_t>::max()),
      lidar_(params_.lidar),
      follower_(params_.follower),
      safety_(params_.safety, footprint) {
  reset_obstacles();
  make_both_ways();
  // At start, not at the first order: the planners' tables for the whole site are the bulk of
  // the agent's memory, which then stays flat while it works.
  hand_grid_to_planners();
}

void Navigation::reset_obstacles() {
  obstacles_.clear();
  for (const auto& o : site_->site.static_obstacles) {
    obstacles_[o.id] = o.enabled_at_start;
    static_grid_.set_obstacle_enabled(o.id, o.enabled_at_start);
  }
}

void Navigation::set_site(std::shared_ptr<const map::SiteMap> site, std::shared_ptr<const map::RoadGraph> route_graph) {
  site_ = std::move(site);
  params_.route_graph = std::move(route_graph);
  static_grid_ = make_static_grid(params_.grid_resolution, *site_);
  reset_obstacles();
  // routes_ keeps a reference to road_: assigned in place, it plans on the new graph.
  road_ = planning::RoadPlanner(params_.route_graph ? *params_.route_graph : site_->graph.graph);
  make_both_ways();
  grid_revision_ = std::numeric_limits<std::uint64_t>::max();
  hand_grid_to_planners();
  follower_.forget_route();
}

void Navigation::make_both_ways() {
  both_ways_.reset();
  if (params_.both_ways_when_closed && params_.route_graph) {
    both_ways_ = std::make_unique<BothWays>(site_->graph.graph, grid_astar_, params_.routes);
  }
}

bool Navigation::set_obstacle(const std::string& id, bool enabled) {
  auto it = obstacles_.find(id);
  if (it == obstacles_.end() || it->second == enabled) return false;
  it->second = enabled;
  static_grid_.set_obstacle_enabled(id, enabled);
  return true;
}

std::vector<geometry::Polygon> Navigation::enabled_obstacles() const {
  std::vector<geometry::Polygon> out;
  for (const auto& o : site_->site.static_obstacles) {
    if (obstacles_.at(o.id)) out.push_back(o.polygon);
  }
  return out;
}

void Navigation::hand_grid_to_planners() {
  // Planners cache on the grid: hand them the new one only when an obstacle changed.
  if (static_grid_.revision() == grid_revision_) return;
  auto grid = std::make_shared<const planning::OccupancyGrid>(static_grid_.grid());
  road_.set_obstacles(*grid);
  if (both_ways_) both_ways_->road.set_obstacles(*grid);
  grid_astar_.set_grid(grid);
  grid_revision_ = static_grid_.revision();
}

planning::Route Navigation::plan(const geometry::Pose2& from, const geometry::Pose2& goal) {
  hand_grid_to_planners();
  planning::Route route = routes_.plan(from, goal);
  if (both_ways_ && route.status != planning::PlanStatus::kFound) {
    planning::Route both_ways = both_ways_->routes.plan(from, goal);
    if (both_ways.status == planning::PlanStatus::kFound) route = std::move(both_ways);
  }
  return route;
}

planning::LidarScan Navigation::scan(const geometry::Pose2& truth, const geometry::Pose2& estimate) const {
  std::vector<geometry::Polygon> seen = true_neighbours_;
  for (const auto& o : site_->site.static_obstacles) {
    if (obstacles_.at(o.id)) seen.push_back(o.polygon);
  }
  planning::LidarScan scan = lidar_.scan(truth, seen);
  scan.pose = estimate;
  return scan;
}

}  // namespace fleet::robot
