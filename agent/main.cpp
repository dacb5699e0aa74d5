// fleet-agent: one robot. Simulates its body and runs its software against it over DDS.

#include <csignal>
#include <iostream>
#include <memory>

#include "agent/fleet_agent.hpp"
#include "common/args.hpp"
#include "common/paths.hpp"
#include "common/process_memory.hpp"
#include "dds/environment.hpp"
#include "model/names.hpp"

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop = true; }

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
  std::string config_path = default_config_path();
  try {
    Args args(argc, argv);
    if (args.flag("help")) {
      std::cout << kHelp;
      return 0;
    }
    if (auto c = args.value("config")) config_path = *c;
    config::FleetConfig config = config::load_fleet_config(config_path);
    const auto id = args.value("id");
    if (!id) throw ArgError("--id ROBOT is required");
    config::apply_common_flags(args, config);
    const bool verbose = args.flag("verbose");
    if (const auto rest = args.positionals(); !rest.empty()) throw ArgError("unexpected argument '" + rest[0] + "'");

    const auto robot = config.find_robot(*id);
    if (!robot) {
      std::vector<std::string> ids;
      for (const auto& [f, r] : config.all_robots()) ids.push_back(r->id);
      throw ArgError("--id: " + model::unknown_name_message("robot", *id, ids) + " (declared in " + config.source + ")");
    }
    const std::string site_file = map::site_path(maps_dir(), config.settings.get_string("site"));
    auto site_map = std::make_shared<const map::SiteMap>(map::load_site_map(site_file));
    const map::Site& site = site_map->site;
    if (!site.find_home(robot->second->home)) {
      throw config::ConfigError(config.source + ": robot '" + *id + "': home '" + robot->second->home +
                                "' is not a home of " + site_file);
    }

    dds::use_fleet_dds_config();
    ProcessMemory::limit_arenas();
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);

    agent::AgentOptions options;
    options.robot_id = *id;
    options.domain = static_cast<std::uint32_t>(config.settings.get_int("dds.domain"));
    options.time_scale = config.settings.get_double("time_scale");
    options.seed = static_cast<std::uint64_t>(config.settings.get_int("seed"));
    options.config = std::move(config);
    options.site = std::move(site_map);
    auto log = make_logger("fleet-agent", *id, verbose ? spdlog::level::debug : spdlog::level::info);
    agent::FleetAgent fleet_agent(std::move(options), log);
    fleet_agent.run(g_stop);
    return 0;
  } catch (const ArgError& e) {
    std::cerr << "fleet-agent: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "fleet-agent: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "fleet-agent: " << e.what() << "\n";
    return 1;
  }
}
