// fleet-server: orders, dispatch, fleet registry, site state and pose routing over DDS.

#include <csignal>
#include <filesystem>
#include <iostream>

#include "common/args.hpp"
#include "common/paths.hpp"
#include "dds/environment.hpp"
#include "server/fleet_server.hpp"

namespace {

std::atomic<bool> g_stop{false};

void on_signal(int) { g_stop = true; }

constexpr const char* kHelp = R"(usage: fleet-server [options]

The Fleet server: takes transport orders, dispatches them to robots, tracks robot health,
owns the site (map, static obstacles, pallets) and routes robot poses, all over Cyclone DDS.

options:
  --config FILE        configuration (default: config/fleet.yaml)
  --domain N           DDS domain id (default: dds.domain)
  --site NAME          site to serve: maps/NAME.yaml (default: site)
  --time-scale K       sim_time = K x wall time (default: time_scale)
  --seed S             seed of the random order generator (default: seed)
  --dispatch POLICY    ascending-id | nearest | optimal (default: server.dispatch_policy)
  --db FILE            SQLite database of orders (default: server.db_path, var/fleet.db)
  --auto-orders        create random orders whenever a robot is free
  --verbose            log debug events too
  --help               this text

Logs go to stderr, one line per event. SIGINT or SIGTERM stops it cleanly.
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
    if (auto v = args.value("domain")) config.settings.set("dds.domain", *v, "--domain");
    if (auto v = args.value("site")) config.settings.set("site", *v, "--site");
    if (auto v = args.value("time-scale")) config.settings.set("time_scale", *v, "--time-scale");
    if (auto v = args.value("seed")) config.settings.set("seed", *v, "--seed");
    if (auto v = args.value("dispatch")) config.settings.set("server.dispatch_policy", *v, "--dispatch");
    if (auto v = args.value("db")) config.settings.set("server.db_path", *v, "--db");
    if (args.flag("auto-orders")) config.settings.set("server.auto_orders", "true", "--auto-orders");
    const bool verbose = args.flag("verbose");
    if (const auto rest = args.positionals(); !rest.empty()) throw ArgError("unexpected argument '" + rest[0] + "'");

    const std::string site_file = map::site_path(maps_dir(), config.settings.get_string("site"));
    map::Site site = map::load_site(site_file);
    for (const auto& [fleet, robot] : config.all_robots()) {
      if (!site.find_home(robot->home)) {
        throw config::ConfigError(config.source + ": robot '" + robot->id + "': home '" + robot->home +
                                  "' is not a home of " + site_file);
      }
    }

    dds::use_fleet_dds_config();
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);

    server::ServerOptions options;
    options.domain = static_cast<std::uint32_t>(config.settings.get_int("dds.domain"));
    options.time_scale = config.settings.get_double("time_scale");
    options.seed = static_cast<std::uint64_t>(config.settings.get_int("seed"));
    const std::filesystem::path db(config.settings.get_string("server.db_path"));
    options.db_path = (db.is_absolute() ? db : std::filesystem::path(project_root()) / db).string();
    options.config = std::move(config);
    options.site = std::move(site);
    auto log = make_logger("fleet-server", "", verbose ? spdlog::level::debug : spdlog::level::info);
    server::FleetServer fleet_server(std::move(options), log);
    fleet_server.run(g_stop);
    return 0;
  } catch (const ArgError& e) {
    std::cerr << "fleet-server: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const config::ConfigError& e) {
    std::cerr << "fleet-server: " << e.what() << "\n";
    return 2;
  } catch (const map::MapError& e) {
    std::cerr << "fleet-server: " << e.what() << "\n";
    return 2;
  } catch (const server::StoreError& e) {
    std::cerr << "fleet-server: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "fleet-server: " << e.what() << "\n";
    return 1;
  }
}
