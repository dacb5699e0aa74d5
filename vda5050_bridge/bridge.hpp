#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "dds/topics.hpp"
#include "emulation/emulated_robot.hpp"
#include "map/site_map.hpp"
#include "mqtt_link/mqtt_link.hpp"
#include "orders/assignment_intake.hpp"
#include "vda5050/messages.hpp"
#include "vda5050/vehicle_master.hpp"

namespace fleet::vda5050_bridge {

struct BridgeOptions {
  config::FleetConfig config;
  std::shared_ptr<const map::SiteMap> site;
  std::uint32_t domain = 0;
  double time_scale = 1.0;
  std::uint64_t seed = 1;         ///< unused: the bridge draws nothing at random
  std::string broker;             ///< tcp://HOST:PORT
  double state_timeout_s = 35.0;  ///< wall seconds without state before a vehicle is lost
  double state_hz = 10.0;         ///< RobotState and traffic progress per wall second
  std::string figures_file;       ///< where to write the figures as JSON at the end; "" for none
};

/// fleet-vda5050: Fleet as VDA 5050 master control of every vehicle of the fleets of robot type
/// vda5050 (docs/vda5050.md). To the server each vehicle is a robot like any other: the bridge
/// speaks for it on DDS as an agent does (RobotState, TrafficRequest, OrderState, RobotPath) and
/// takes its orders and grants; to the vehicle it is the master, over MQTT.
class Bridge {
 public:
  Bridge(BridgeOptions options, Logger log);
  void run(const std::atomic<bool>& stop);

  /// What the bridge cost and how fast it passes grants on, since it started: its CPU (percent of
  /// one core, and per vehicle it drove: each that was online at some time), and the wall seconds from a grant that
  /// reaches further (its DDS source time) to the broker's acknowledgement of the order update it released.
  nlohmann::json figures() const;

 private:
  struct Vehicle {
    const config::FleetSpec* fleet = nullptr;
    vda5050::VehicleAddress address;
    std::unique_ptr<vda5050::VehicleMaster> master;
    std::shared_ptr<emulation::EmulatedRoutes> routes;
    std::string connection;                           ///< the last connectionState, "" before any
    double last_state_wall = -1.0;                    ///< wall time of its last state, -1 before any
    bool online = false;                              ///< speaking for it on DDS
    bool was_lost = false;                            ///< online before, then lost
    std::map<std::string, std::uint32_t> header_ids;  ///< per topic
    double next_bad_message_log = 0.0;
    std::string factsheet;         ///< the last factsheet read, to report a change once
    bool state_requested = false;  ///< a stateRequest went out since the last state
    // The order as the server sees it.
    std::int64_t order_id = 0;
    std::uint32_t update_id = 0;
    std::string phase;
    orders::AssignmentIntake intake;
    std::uint64_t sent_version = 0;
    bool sent_off_road = false;
    std::size_t path_size = 0;
    // The newest grant, and the source time of one that reached further and is not yet passed on.
    std::uint64_t grant_version = 0;
    double grant_distance = -1.0;
    double grant_source_wall = -1.0;
  };

  void cycle(double now_wall, double now_sim);
  void take_mqtt(double now_wall);
  void take_message(Vehicle& v, const std::string& kind, const std::string& payload, double now_wall);
  void take_orders(double now_sim);
  void take_order(Vehicle& v, model::OrderAssignment&& a, double now_sim);
  void take_grants();
  void take_pallets();
  void take_controls();
  void watch_liveness(Vehicle& v, double now_wall);
  void check_factsheet(Vehicle& v, const nlohmann::json& message);
  void send(Vehicle& v, double now_wall);
  void report(Vehicle& v, const std::string& status, double now_sim, int pallet_id = -1,
              const geometry::Pose2& pallet_pose = {}, const std::string& reason = "");
  void publish(Vehicle& v, double now_sim);

  BridgeOptions options_;
  Logger log_;
  std::vector<Vehicle> vehicles_;
  std::unordered_map<std::string, std::size_t> by_robot_;
  std::unordered_map<std::string, std::size_t> by_topic_prefix_;  ///< "{iface}/v2/{manufacturer}/{serial}/"
  std::map<std::string, int> load_at_;
  std::map<std::string, double> unknown_reported_;

  double started_wall_ = 0.0;
  mutable std::mutex latency_mutex_;
  std::vector<double> grant_to_broker_s_;  ///< filled on the MQTT client's thread
  std::unique_ptr<mqtt_link::MqttLink> mqtt_;
  dds::Participant participant_;
  // Each vehicle's reports go out in its robot's own partition, as an agent's do: with DDS
  // Security that partition is what the server takes as the writer's identity.
  dds::PartitionWriters<model::RobotState> state_writer_;
  dds::PartitionWriters<model::OrderReport> report_writer_;
  dds::PartitionWriters<model::RobotPath> path_writer_;
  dds::PartitionWriters<model::TrafficRequest> traffic_writer_;
  dds::PartitionWriters<model::SimTruth> truth_writer_;
  dds::Reader<model::TrafficGrant> grant_reader_;
  dds::Reader<model::OrderAssignment> order_reader_;
  dds::Reader<model::PalletTruth> pallet_reader_;
  dds::Reader<model::RobotControl> control_reader_;
};

}  // namespace fleet::vda5050_bridge
