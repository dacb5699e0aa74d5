// fleet-agent: one robot. Simulates its body and runs its software against it over DDS.

#include <iostream>
#include <memory>

#include "agent/fleet_agent.hpp"
#include "agent/vda5050_vehicle.hpp"
#include "app/process.hpp"
#include "model/names.hpp"

namespace {

constexpr const char* kHelp = R"(usage: fleet-agent --id ROBOT [options]

One Fleet robot: simulates its body and sensors and runs its own software (localization,
planning, control, task state machine) against them, talking to fleet-server over Cyclone DDS.

options:
  --id ROBOT           robot id, one of the robots declared under fleets in the configuration
  --config FILE        configuration (default: config/fleet.yaml)
  --domain N           DDS domain id (default: dds.domain)
  --site NAME          site: maps/NAME.yaml (default: site)
  --time-scale K       sim_time = K x wall time (default: time_scale)
  --seed S             seed of every noise source (default: seed; the robot id is mixed in)
  --security DIR       join the DDS domain with DDS Security as robot ROBOT, with the credentials
                       of DIR (fleetctl security init; default: dds.security, empty: without)
  --set KEY=VALUE      any configuration key (repeatable), e.g. --set traffic.enabled=false
  --vda5050 BROKER     be a VDA 5050 vehicle instead: take orders from a master control on the
                       MQTT broker tcp://HOST:PORT, speak no DDS (docs/vda5050.md)
  --vda5050-manufacturer M  its manufacturer in topics and headers (default: Fleet)
  --vda5050-interface I     its interface name (default: uagv)
  --vda5050-version V       2.0.0 or 2.1.0 (default: 2.0.0)
  --verbose            log debug events too
  --help               this text

Logs go to stderr, one line per event, prefixed with the robot id. SIGINT or SIGTERM stops it.
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace fleet;
  try {
    Args args(argc, argv);
    auto config = app::read_config(args, kHelp, std::cout);
    if (!config) return 0;
    const auto id = args.value("id");
    if (!id) throw ArgError("--id ROBOT is required");
    const auto broker = args.value("vda5050");
    const vda5050::VehicleAddress address{args.value("vda5050-interface").value_or("uagv"),
                                          args.value("vda5050-version").value_or("2.0.0"),
                                          args.value("vda5050-manufacturer").value_or("Fleet"), *id};
    if (address.version != "2.0.0" && address.version != "2.1.0") {
      throw ArgError("--vda5050-version: '" + address.version + "' is neither 2.0.0 nor 2.1.0");
    }
    const auto level = app::finish_args(args);

    const auto robot = config->find_robot(*id);
    if (!robot) {
      std::vector<std::string> ids;
      for (const auto& [f, r] : config->all_robots()) ids.push_back(r->id);
      throw ArgError("--id: " + model::unknown_name_message("robot", *id, ids) + " (declared in " + config->source +
                     ")");
    }
    auto site_map = app::load_site(*config, {*id});
    if (broker) {
      agent::VehicleOptions options;
      options.robot_id = *id;
      options.broker = *broker;
      options.address = address;
      options.time_scale = config->settings.get_double("time_scale");
      options.seed = static_cast<std::uint64_t>(config->settings.get_int("seed"));
      options.config = std::move(*config);
      options.site = std::move(site_map);
      const std::atomic<bool>& stop = app::start_daemon();
      agent::Vda5050Vehicle vehicle(std::move(options), make_logger("fleet-agent", *id, level));
      vehicle.run(stop);
      return 0;
    }
    const std::atomic<bool>& stop = app::start_daemon();
    app::use_dds_security(config->settings.get_string("dds.security"), *id, "dds.security");

    agent::AgentOptions options;
    options.robot_id = *id;
    app::set_run_options(options, *config);
    options.config = std::move(*config);
    options.site = std::move(site_map);
    agent::FleetAgent fleet_agent(std::move(options), make_logger("fleet-agent", *id, level));
    fleet_agent.run(stop);
    return 0;
  } catch (...) {
    return app::exit_code_of_current_exception("fleet-agent", std::cerr, true);
  }
}
