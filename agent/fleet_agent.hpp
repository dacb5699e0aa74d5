#pragma once

#include <atomic>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>

#include "agent/map_loader.hpp"
#include "common/clock.hpp"
#include "common/logging.hpp"
#include "common/step_lag.hpp"
#include "config/fleet_config.hpp"
#include "dds/topics.hpp"
#include "map/site_map.hpp"
#include "orders/assignment_intake.hpp"
#include "robot/neighbour_memory.hpp"
#include "robot/robot.hpp"
#include "robot/robot_factory.hpp"

namespace fleet::agent {

struct AgentOptions {
  config::FleetConfig config;
  std::shared_ptr<const map::SiteMap> site;
  std::string robot_id;
  std::uint32_t domain = 0;
  double time_scale = 1.0;
  std::uint64_t seed = 1;
};

/// One robot process: a robot::Robot of its fleet's robot type (simulated body and sensors, and
/// the robot's own software, built by robot::make_robot) wired to the server over DDS. Everything
/// the robot learns arrives here as a message; everything it does leaves as one.
class FleetAgent {
 public:
  FleetAgent(AgentOptions options, Logger log);

  /// Runs until `stop` becomes true.
  void run(const std::atomic<bool>& stop);

 private:
  struct CurrentOrder {
    model::OrderAssignment assignment;
    std::string phase;
  };

  /// A pick order's lines as the robot drives them, each place's pose from the site; empty when
  /// they can be read, else why not.
  std::string item_stops(const model::OrderAssignment& assignment, std::vector<task::ItemStop>& stops) const;

  void handle_orders();
  /// The order the robot runs, updated by the server: a loader walk's release, or where a
  /// transport with no drop area yet stands with its load, or its drop area.
  void update_running_order(const model::OrderAssignment& assignment);
  /// The server withdraws the order the robot runs.
  void withdraw(std::int64_t order_id);
  /// A new order: checked against the intake's rules, then submitted to the robot or rejected.
  void consider(const model::OrderAssignment& assignment);
  void handle_site_inputs();
  void handle_fleet_view(double now_sim);
  /// Simulation only: the other robots' true bodies for the simulated sensors, from the latest
  /// view (null when none came this time) or, while views stay away, from SimTruth itself.
  void take_true_bodies(std::optional<model::NeighbourView>& latest);
  /// Drives on `loaded` from now on: the map the server assigned, read by map_loader_.
  void switch_map(LoadedMap loaded);
  void handle_events();
  /// Writes an OrderReport on the current order; nothing when there is none.
  std::optional<model::OrderReport> report(const std::string& status, const std::string& reason = "",
                                           int pallet_id = -1, const geometry::Pose2& pallet_pose = {});
  /// Reports the current order's end (DONE or FAILED), keeps the report and drops the order.
  void finish_order(const std::string& status, const std::string& reason, int pallet_id = -1,
                    const geometry::Pose2& pallet_pose = {});
  void publish_state(double now_sim);
  void publish_traffic(double now_sim);
  void handle_traffic();
  /// After the process stood still long enough for the server to take the robot for lost: the
  /// road granted beyond its body may have gone to others meanwhile, so it stands until a grant
  /// made after `now_sim` arrives.
  void drop_grant(double now_sim);
  void flush_delayed_states();

  AgentOptions options_;
  Logger log_;
  SimClock clock_;
  const config::FleetSpec* fleet_ = nullptr;
  std::unique_ptr<robot::Robot> robot_;
  MapLoader map_loader_;
  StepLagMeter step_lag_;  ///< how late the control steps run (reported in RobotState)
  std::string map_id_;
  std::optional<CurrentOrder> order_;
  std::map<std::string, bool> obstacles_;
  std::map<std::pair<std::string, std::string>, bool> obstacle_cache_;  ///< (map, obstacle) -> enabled
  std::map<int, model::PalletTruth> pallets_;
  std::map<std::string, model::SimTruth> truths_;
  std::unique_ptr<dds::Reader<model::SimTruth>> direct_truths_;  ///< only while no view comes
  double last_view_wall_ = 0.0;
  robot::NeighbourMemory neighbours_;
  /// Which assignments are new, duplicates or withdrawals, and the final reports (DONE or FAILED)
  /// of the last orders, latched for a restarted server and repeated when it offers one again.
  orders::AssignmentIntake intake_;
  bool paused_ = false;
  std::string last_state_;
  std::string last_detail_;
  std::size_t last_path_size_ = 0;
  bool traffic_ = false;
  robot::TrafficRoute last_traffic_;
  std::string last_traffic_map_;
  double last_traffic_sim_ = -1.0;
  double last_route_sent_wall_ = -1e9;
  double grants_valid_from_sim_ = -1.0;  ///< grants stamped earlier are stale (drop_grant)
  // Fault injection (faults.pose_delay_ms): RobotState held back until its wall time is due.
  double pose_delay_s_ = 0.0;
  double pose_jitter_s_ = 0.0;
  std::mt19937_64 delay_rng_;
  std::deque<std::pair<double, model::RobotState>> delayed_states_;

  dds::Participant participant_;
  dds::Writer<model::RobotState> state_writer_;
  dds::Writer<model::SimTruth> truth_writer_;
  dds::Writer<model::OrderReport> report_writer_;
  dds::Writer<model::RobotPath> path_writer_;
  dds::Writer<model::TrafficRequest> traffic_writer_;
  dds::Writer<model::TrafficProgress> progress_writer_;
  /// Its traffic grants, in its own partition (model::robot_partition).
  dds::Reader<model::TrafficGrant> grant_reader_;
  dds::Reader<model::OrderAssignment> order_reader_;
  dds::Reader<model::MapAssignment> map_reader_;
  dds::Reader<model::StaticObstacleState> obstacle_reader_;
  dds::Reader<model::RobotControl> control_reader_;
  dds::Reader<model::PalletTruth> pallet_reader_;
  /// The robots near this one, in its own partition (model::robot_partition).
  dds::Reader<model::NeighbourView> neighbour_reader_;
  dds::WaitSet waitset_;
};

}  // namespace fleet::agent
