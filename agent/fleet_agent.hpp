#pragma once

#include <atomic>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include "common/clock.hpp"
#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "dds/topics.hpp"
#include "map/site.hpp"

namespace fleet::agent {

struct AgentOptions {
  config::FleetConfig config;
  map::Site site;
  std::string robot_id;
  std::uint32_t domain = 0;
  double time_scale = 1.0;
  std::uint64_t seed = 1;
};

/// One robot: simulates its body and runs its software against it, talking to the server over
/// DDS only.
class FleetAgent {
 public:
  FleetAgent(AgentOptions options, Logger log);

  /// Runs until `stop` becomes true.
  void run(const std::atomic<bool>& stop);

 private:
  struct ActiveOrder {
    model::OrderAssignment assignment;
    std::string phase;
  };

  void handle_orders();
  void handle_site_inputs();
  void step(double dt);
  void set_phase(const std::string& phase, const std::string& task_state);
  void report(std::int64_t order_id, std::uint32_t update_id, const std::string& status,
              const std::string& reason = "");
  void publish_state(double now_sim);
  void retire_report(std::int64_t order_id);
  /// Where the forklift stands to pick from or drop onto `area` (facing the pallet).
  geometry::Pose2 service_pose(const geometry::Pose2& area) const;
  /// Kinematic motion towards `target`: turn, drive, turn. Returns true on arrival.
  bool drive_towards(const geometry::Pose2& target, double dt);

  AgentOptions options_;
  Logger log_;
  SimClock clock_;
  const config::FleetSpec* fleet_ = nullptr;
  geometry::Pose2 home_;
  geometry::Pose2 pose_;
  double speed_ = 0.0;
  double yaw_rate_ = 0.0;
  std::string task_state_ = "IDLE";
  std::string map_id_;
  std::optional<ActiveOrder> order_;
  bool carrying_pallet_ = false;
  double phase_timer_ = 0.0;
  std::map<std::int64_t, std::uint32_t> seen_updates_;  ///< order id -> newest update id handled
  std::map<std::string, bool> obstacles_;
  std::deque<std::int64_t> finished_orders_;
  bool paused_ = false;

  dds::Participant participant_;
  dds::Writer<model::RobotState> state_writer_;
  dds::Writer<model::SimTruth> truth_writer_;
  dds::Writer<model::OrderReport> report_writer_;
  dds::Writer<model::RobotPath> path_writer_;
  dds::Reader<model::OrderAssignment> order_reader_;
  dds::Reader<model::MapAssignment> map_reader_;
  dds::Reader<model::StaticObstacleState> obstacle_reader_;
  dds::Reader<model::RobotControl> control_reader_;
  dds::WaitSet waitset_;
};

}  // namespace fleet::agent
