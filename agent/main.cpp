// fleet-agent: one robot. Simulates its body and runs its software against it over DDS.

#include <iostream>
#include <memory>

#include "agent/fleet_agent.hpp"
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
  --set KEY=VALUE      any configuration key (repeatable), e.g. --set traffic.enabled=false
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
    const auto level = app::finish_args(args);

    const auto robot = config->find_robot(*id);
    if (!robot) {
      std::vector<std::string> ids;
      for (const auto& [f, r] : config->all_robots()) ids.push_back(r->id);
      throw ArgError("--id: " + model::unknown_name_message("robot", *id, ids) + " (declared in " + config->source +
                     ")");
    }
    auto site_map = app::load_site(*config, {*id});
    const std::atomic<bool>& stop = app::start_daemon();

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
