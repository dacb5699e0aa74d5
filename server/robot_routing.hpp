#pragma once
// What the server tells about where the robots are: the full FleetView for observers (the soak's
// watch, fleetctl routing-age) and, for each agent, the NeighbourView of the robots near it, with
// the true bodies near it in simulation. It takes the robots' planned paths and (simulation only)
// true poses, which go into the views and the web view.

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/clock.hpp"
#include "config/fleet_config.hpp"
#include "dds/topics.hpp"
#include "orders/robot_roster.hpp"
#include "server/sender_gate.hpp"

namespace fleet::server {

class RobotRouting {
 public:
  /// `config` (server.fleet_view_hz, server.neighbour_radius, the robots' footprints) and `clock`
  /// must outlive it. Its views count as complete a while after the first ones (the server loop's start).
  RobotRouting(dds::Participant& participant, const config::FleetConfig& config, const SimClock& clock);

  /// The reader whose samples should wake the server loop (the paths).
  dds_entity_t path_reader() const { return path_reader_.handle(); }

  /// Takes the robots' paths and true poses, from writers `gate` admits.
  void take_reports(SenderGate& gate);

  /// The FleetView and each robot's NeighbourView, when due (server.fleet_view_hz, capped in
  /// wall rate); robots without a map of their own are on `default_map`.
  void publish_when_due(const orders::RobotRoster& robots, const std::string& default_map);

  /// Opens the partition of `robot_id`'s NeighbourView (once, when it first reports).
  void open_view_of(const std::string& robot_id);

  /// The planned path `robot_id` reported last (empty when none).
  std::vector<geometry::Vec2> path_of(const std::string& robot_id) const;
  /// Its true pose (simulation only; nothing when none came).
  std::optional<model::SimTruth> truth_of(const std::string& robot_id) const;

 private:
  using Snapshots = std::vector<std::pair<std::string, model::RobotSnapshot>>;  // map id, robot

  void publish_neighbour_views(const Snapshots& snapshots, double now_wall);
  /// Simulation only: the true bodies within the view's radius of its robot's true body.
  void add_true_bodies(model::NeighbourView& view, const geometry::Pose2& estimate) const;

  const config::FleetConfig& config_;
  const SimClock& clock_;
  double first_published_wall_ = 0.0;  ///< the server loop's first views
  double last_published_wall_ = 0.0;
  std::map<std::string, model::RobotPath> paths_;
  std::map<std::string, model::SimTruth> truths_;
  dds::Reader<model::RobotPath> path_reader_;
  dds::Reader<model::SimTruth> truth_reader_;
  dds::Writer<model::FleetView> fleet_view_writer_;
  /// One per robot, each in the robot's own partition (model::robot_partition).
  dds::PartitionWriters<model::NeighbourView> neighbour_writers_;
};

}  // namespace fleet::server
