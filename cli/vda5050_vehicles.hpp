#pragma once

#include <string>
#include <vector>

#include "cli/processes.hpp"
#include "config/fleet_config.hpp"
#include "map/site.hpp"

namespace fleet::cli {

/// What `--vda5050-vehicles N` starts beside a demo's or soak's fleet: a mosquitto broker of its
/// own on 127.0.0.1 (a free port, a configuration in the run folder), fleet-vda5050, and N
/// simulated VDA 5050 vehicles (vda-5050-lib's VirtualAgvAdapter, tests/vda5050/virtual_agvs.js,
/// one Node.js process per fleet), parked at their homes. A simulation of other makers' vehicles,
/// said so in its log.
struct Vda5050Vehicles {
  std::string broker;  ///< tcp://127.0.0.1:PORT
  std::vector<std::string> robot_ids;
};

/// The first N robots of the configuration's fleets of robot type vda5050, round robin over the
/// fleets; ArgError when it declares fewer.
std::vector<std::pair<const config::FleetSpec*, const config::RobotSpec*>> pick_vda5050_vehicles(
    const config::FleetConfig& config, int count);

/// Starts a mosquitto broker of the run's own on 127.0.0.1 (a free port, its configuration and
/// log in `run_dir`) in `processes` and waits until it listens; its address, tcp://127.0.0.1:PORT.
/// Throws when mosquitto is missing or does not listen within 10 s.
std::string start_mqtt_broker(ProcessGroup& processes, const std::string& run_dir);

/// Starts the broker, the bridge (`bridge_argv` plus --broker, and --figures into
/// `run_dir`/vda5050-figures.json) and the vehicles in `processes`,
/// logs in `run_dir`; `vehicle_args` go to every vehicles' process (tests: --reject-orders SERIAL). The vehicles run
/// `time_scale` times faster than the wall clock, as the rest of the fleet (vda-5050-lib's time lapse). Throws naming
/// what is missing (mosquitto, node, the vehicles' packages).
Vda5050Vehicles start_vda5050_vehicles(ProcessGroup& processes, const config::FleetConfig& config,
                                       const map::Site& site, int count, double time_scale,
                                       std::vector<std::string> bridge_argv, const std::string& run_dir,
                                       const std::vector<std::string>& vehicle_args = {});

}  // namespace fleet::cli
