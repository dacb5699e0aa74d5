// What the server tells about where the robots are: the full FleetView for observers (the soak's
// watch, fleetctl routing-age) and, for each agent, the NeighbourView of the robots near it.

#include <algorithm>
#include <cmath>

#include "dds/qos.hpp"
#include "robot/neighbour_memory.hpp"
#include "server/fleet_server.hpp"

namespace fleet::server {

namespace {

constexpr double kMaxRoutingHzWall = 100.0;  // the views are capped in wall rate at high time scales
/// Wall seconds after the start before a NeighbourView counts as complete: by then every robot
/// that is alive has reported (they report at agent.state_hz) and the server knows where it is.
/// A robot that stands frozen across a restart reports later; the views wait for the agents'
/// forgetting time as well (robot::NeighbourMemory::kForgetAfterS), after which an agent would no
/// longer keep it either way.
constexpr double kViewsCompleteAfterWall = 3.0;

}  // namespace

void FleetServer::publish_fleet_view() {
  const double now_wall = SimClock::wall_now();
  const double period_wall = std::max(
      1.0 / kMaxRoutingHzWall, clock_.to_wall(1.0 / options_.config.settings.get_double("server.fleet_view_hz")));
  if (now_wall - last_fleet_view_wall_ < period_wall) return;
  last_fleet_view_wall_ = now_wall;
  // Paths go to observers only, and only when one listens: hundreds of robots with routes of
  // hundreds of points make megabytes a view.
  const bool observed = fleet_view_writer_.matched() > 0;
  std::map<std::string, model::FleetView> views;
  std::vector<std::pair<std::string, model::RobotSnapshot>> snapshots;  // map id, robot
  for (const auto& [id, robot] : robots_.entries()) {
    if (!robot.registered) continue;
    const auto spec = options_.config.find_robot(id);
    model::RobotSnapshot snap;
    snap.robot_id = id;
    snap.fleet_id = robot.fleet_id;
    snap.pose = robot.last.pose;
    if (spec) snap.footprint = spec->first->footprint;
    snap.speed = robot.last.speed;
    snap.task_state = robot.lost ? "LOST" : robot.last.task_state;
    snap.sim_time = robot.last.sim_time;
    const std::string map_id = robot.last.map_id.empty() ? options_.site.name : robot.last.map_id;
    if (observed) {
      auto& view = views[map_id];
      view.map_id = map_id;
      view.sim_time = clock_.now();
      view.robots.push_back(snap);
      if (auto p = paths_.find(id); p != paths_.end()) view.robots.back().path = p->second.points;
    }
    snapshots.emplace_back(map_id, std::move(snap));
  }
  for (const auto& [map_id, view] : views) fleet_view_writer_.write(view);
  publish_neighbour_views(snapshots, now_wall);
}

void FleetServer::publish_neighbour_views(const std::vector<std::pair<std::string, model::RobotSnapshot>>& snapshots,
                                          double now_wall) {
  const double radius = options_.config.settings.get_double("server.neighbour_radius");
  const double complete_after_wall =
      std::max(kViewsCompleteAfterWall, clock_.to_wall(robot::NeighbourMemory::kForgetAfterS));
  const bool complete = now_wall - started_wall_ >= complete_after_wall;
  // By x, so that each robot looks only at the strip of robots within the radius along x.
  std::vector<std::size_t> by_x(snapshots.size());
  for (std::size_t i = 0; i < by_x.size(); ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(),
            [&](std::size_t a, std::size_t b) { return snapshots[a].second.pose.x < snapshots[b].second.pose.x; });
  for (std::size_t k = 0; k < by_x.size(); ++k) {
    const auto& [map_id, me] = snapshots[by_x[k]];
    model::NeighbourView view{me.robot_id, map_id, clock_.now(), radius, complete, {}, {}};
    const auto near = [&](std::size_t j) {
      const auto& [other_map, other] = snapshots[by_x[j]];
      const double dx = other.pose.x - me.pose.x;
      const double dy = other.pose.y - me.pose.y;
      if (other_map == map_id && dx * dx + dy * dy <= radius * radius) view.robots.push_back(other);
    };
    for (std::size_t j = k; j-- > 0 && me.pose.x - snapshots[by_x[j]].second.pose.x <= radius;) near(j);
    for (std::size_t j = k + 1; j < by_x.size() && snapshots[by_x[j]].second.pose.x - me.pose.x <= radius; ++j) near(j);
    add_true_bodies(view, me.pose);
    neighbour_writers_.write(model::robot_partition(me.robot_id), view);
  }
}

void FleetServer::add_true_bodies(model::NeighbourView& view, const geometry::Pose2& estimate) const {
  // Simulation only. Each agent's simulated sensors see the true bodies of the robots near its
  // own true body; relayed here, an agent receives one view instead of every robot's SimTruth.
  const auto own = truths_.find(view.robot_id);
  const geometry::Vec2 centre = own != truths_.end() ? own->second.pose.position() : estimate.position();
  for (const auto& [id, truth] : truths_) {
    if (id == view.robot_id || !geometry::is_finite(truth.pose)) continue;
    if (geometry::distance(truth.pose.position(), centre) <= view.radius) view.bodies.push_back(truth);
  }
}

}  // namespace fleet::server
