#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "mqtt_link/mqtt_link.hpp"
#include "robot/robot.hpp"
#include "vda5050/messages.hpp"
#include "vda5050/vehicle_drive.hpp"
#include "vda5050/vehicle_order.hpp"

namespace fleet::agent {

struct VehicleOptions {
  config::FleetConfig config;
  std::shared_ptr<const map::SiteMap> site;
  std::string robot_id;
  double time_scale = 1.0;
  std::uint64_t seed = 1;
  std::string broker;  ///< tcp://127.0.0.1:PORT
  /// interface name, version, manufacturer and serial number (the robot id) it answers to.
  vda5050::VehicleAddress address;
  double visualization_period_s = 1.0;  ///< wall seconds between `visualization` messages
  double state_period_s = 30.0;         ///< wall seconds between `state` messages without an event
};

/// One of Fleet's robots (a robot::Robot of its fleet's type, simulated body and sensors) driven
/// by a foreign master control over VDA 5050 instead of by fleet-server: it answers on MQTT as a
/// vehicle does [VDA 5050, sections 6.6-6.14] and speaks no DDS. The decisions live in
/// core/vda5050 (VehicleOrder, job_of, VehicleDrive); this class wires them to the robot and the
/// broker. Without a server, the loads standing on the site are its own simulation truth, from
/// the site's loading areas.
class Vda5050Vehicle {
 public:
  Vda5050Vehicle(VehicleOptions options, Logger log);

  /// Runs until `stop` becomes true; then says OFFLINE and disconnects.
  void run(const std::atomic<bool>& stop);

 private:
  void handle_messages();
  void on_order(const nlohmann::json& message);
  void on_instant_actions(const nlohmann::json& message);
  void instant_action(const vda5050::ReceivedAction& action);
  /// Runs `next` from now on: the job under way goes on (a new base, or the drop of a pick that
  /// came alone), or the robot is given `next`'s order. The error that refuses it otherwise.
  std::optional<vda5050::VehicleError> take_job(const vda5050::VehicleJob& next, bool under_way,
                                                const nlohmann::json& message);
  /// The leg being driven (to the pick, then to the drop) from the nodes ahead.
  void update_leg();
  /// Grants the robot its route up to the base end, and passes the nodes it has reached.
  void drive();
  void handle_events();
  void reject(const vda5050::VehicleError& error);
  /// The order's phase events as action states and passed nodes.
  void on_phase(const std::string& phase);

  void publish(const std::string& topic, const nlohmann::json& body, int qos = 0, bool retained = false);
  void publish_state();
  void publish_visualization();
  void publish_connection(const std::string& state);
  void publish_factsheet();
  nlohmann::json position_json() const;

  VehicleOptions options_;
  Logger log_;
  SimClock clock_;
  const config::FleetSpec* fleet_ = nullptr;
  std::unique_ptr<robot::Robot> robot_;
  std::unique_ptr<mqtt_link::MqttLink> mqtt_;
  int connections_seen_ = 0;
  std::map<std::string, std::uint32_t> header_ids_;  ///< per topic

  vda5050::VehicleOrder order_;
  vda5050::VehicleDrive drive_;
  std::optional<vda5050::VehicleJob> job_;
  bool picked_ = false;  ///< the job's pick is done: the leg leads to the drop
  std::vector<vda5050::VehicleError> errors_;
  bool paused_ = false;
  std::map<int, geometry::Pose2> standing_loads_;  ///< simulation truth: load id -> pose
  bool state_due_ = true;                          ///< an event happened: publish state now
  double last_state_wall_ = 0.0;
  double last_visualization_wall_ = 0.0;
  bool last_driving_ = false;
};

}  // namespace fleet::agent
