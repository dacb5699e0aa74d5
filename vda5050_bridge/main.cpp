// fleet-vda5050: Fleet as VDA 5050 master control of other makers' vehicles, over MQTT.

#include <unistd.h>

#include <iostream>
#include <memory>

#include "app/process.hpp"
#include "common/errors.hpp"
#include "security/security_folder.hpp"
#include "vda5050_bridge/bridge.hpp"

namespace {

constexpr const char* kHelp = R"(usage: fleet-vda5050 [options]

Fleet as VDA 5050 master control: drives every vehicle of the configuration's fleets of robot
type vda5050 over an MQTT broker, and speaks for each on Cyclone DDS as an agent does, so that
fleet-server dispatches, coordinates and shows it like any robot (docs/vda5050.md).

options:
  --broker URI         the MQTT broker, tcp://HOST:PORT (default: vda5050.broker)
  --config FILE        configuration (default: config/fleet.yaml)
  --domain N           DDS domain id (default: dds.domain)
  --site NAME          site: maps/NAME.yaml (default: site)
  --time-scale K       sim_time = K x wall time (default: time_scale); the vehicles run in wall time
  --security DIR       join the DDS domain with DDS Security as 'vda5050', with the credentials
                       of DIR (fleetctl security init; default: dds.security, empty: without)
  --figures FILE       at the end, write the bridge's CPU and grant-to-broker latency there (JSON)
  --set KEY=VALUE      any configuration key (repeatable)
  --verbose            log debug events too
  --help               this text

Logs go to stderr, one line per event. SIGINT or SIGTERM stops it.
)";

}  // namespace

int main(int argc, char** argv) {
  using namespace fleet;
  try {
    Args args(argc, argv);
    auto config = app::read_config(args, kHelp, std::cout);
    if (!config) return 0;
    if (auto broker = args.value("broker")) config->settings.set("vda5050.broker", *broker, "--broker");
    const std::string figures_file = args.value("figures").value_or("");
    const auto level = app::finish_args(args);
    std::vector<std::string> ids;
    for (const auto& [fleet, robot] : config->all_robots()) {
      if (fleet->vda5050) ids.push_back(robot->id);
    }
    auto site = app::load_site(*config, ids);
    const std::atomic<bool>& stop = app::start_daemon();
    // One identity for the bridge, whose permissions grant the partitions of its vehicles alone.
    app::use_dds_security(config->settings.get_string("dds.security"), security::kVda5050Identity, "dds.security");

    vda5050_bridge::BridgeOptions options;
    app::set_run_options(options, *config);
    options.broker = config->settings.get_string("vda5050.broker");
    options.state_timeout_s = config->settings.get_double("vda5050.state_timeout_s");
    options.figures_file = figures_file;
    options.config = std::move(*config);
    options.site = std::move(site);
    vda5050_bridge::Bridge bridge(std::move(options), make_logger("fleet-vda5050", "", level));
    bridge.run(stop);
    return 0;
  } catch (...) {
    return app::exit_code_of_current_exception("fleet-vda5050", std::cerr, true);
  }
}
