#include "server/robot_routing.hpp"

#include <algorithm>
#include <cmath>

#include "dds/qos.hpp"
#include "robot/neighbour_memory.hpp"

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

RobotRouting::RobotRouting(dds::Participant& participant, const config::FleetConfig& config, const SimClock& clock)
    : config_(config),
      clock_(clock),
      path_reader_(participant, dds::qos::live_state(), dds::robot_report_partitions()),
      truth_reader_(participant, dds::qos::live_state(), dds::robot_report_partitions()),
      fleet_view_writer_(participant, dds::qos::live_state()),
      neighbour_writers_(participant, dds::qos::live_state()) {}

void RobotRouting::take_reports(SenderGate& gate) {
  path_reader_.take([&](model::RobotPath&& path, const dds::SampleInfo& info) {
    if (info.valid_data && gate.admit(path_reader_.handle(), info, path.robot_id, "fleet/RobotPath")) {
      paths_[path.robot_id] = std::move(path);
    }
  });
  truth_reader_.take([&](model::SimTruth&& truth, const dds::SampleInfo& info) {
    if (info.valid_data && gate.admit(truth_reader_.handle(), info, truth.robot_id, "fleet/SimTruth")) {
      truths_[truth.robot_id] = std::move(truth);
    }
  });
}

void RobotRouting::open_view_of(const std::string& robot_id) {
  neighbour_writers_.open(model::robot_partition(robot_id));
}

std::vector<geometry::Vec2> RobotRouting::path_of(const std::string& robot_id) const {
  const auto p = paths_.find(robot_id);
  return p != paths_.end() ? p->second.points : std::vector<geometry::Vec2>{};
}

std::optional<model::SimTruth> RobotRouting::truth_of(const std::string& robot_id) const {
  const auto t = truths_.find(robot_id);
  if (t == truths_.end()) return std::nullopt;
  return t->second;
}

void RobotRouting::publish_when_due(const orders::RobotRoster& robots, const std::string& default_map) {
  const double now_wall = SimClock::wall_now();
  const double period_wall =
      std::max(1.0 / kMaxRoutingHzWall, clock_.to_wall(1.0 / config_.settings.get_double("server.fleet_view_hz")));
  if (now_wall - last_published_wall_ < period_wall) return;
  last_published_wall_ = now_wall;
  // Paths go to observers only, and only when one listens: hundreds of robots with routes of
  // hundreds of points make megabytes a view.
  const bool observed = fleet_view_writer_.matched() > 0;
  std::map<std::string, model::FleetView> views;
  Snapshots snapshots;
  for (const auto& [id, robot] : robots.entries()) {
    if (!robot.registered) continue;
    const auto spec = config_.find_robot(id);
    model::RobotSnapshot snap;
    snap.robot_id = id;
    snap.fleet_id = robot.fleet_id;
    snap.pose = robot.last.pose;
    if (spec) snap.footprint = spec->first->footprint;
    snap.speed = robot.last.speed;
    snap.task_state = robot.lost ? "LOST" : robot.last.task_state;
    snap.sim_time = robot.last.sim_time;
    const std::string map_id = robot.last.map_id.empty() ? default_map : robot.last.map_id;
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

void RobotRouting::publish_neighbour_views(const Snapshots& snapshots, double now_wall) {
  const double radius = config_.settings.get_double("server.neighbour_radius");
  const double complete_after_wall =
      std::max(kViewsCompleteAfterWall, clock_.to_wall(robot::NeighbourMemory::kForgetAfterS));
  if (first_published_wall_ == 0.0) first_published_wall_ = now_wall;
  const bool complete = now_wall - first_published_wall_ >= complete_after_wall;
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

void RobotRouting::add_true_bodies(model::NeighbourView& view, const geometry::Pose2& estimate) const {
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
