// fleet-server: orders, dispatch, fleet registry, site state and pose routing over DDS.

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include "common/args.hpp"
#include "common/paths.hpp"
#include "common/process_memory.hpp"
#include "dds/environment.hpp"
#include "map/site_map.hpp"
#include "server/fleet_server.hpp"
#include "server/web_server.hpp"

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
  --http-port N        port of the web view and JSON API (default: server.http_port, 8080; 0: off)
  --http-host ADDR     address the web view binds (default: server.http_host, 127.0.0.1)
  --api-token TOKEN    token of the API's mutating calls (default: env FLEET_API_TOKEN, else
                       server.api_token, else one generated at start and logged)
  --set KEY=VALUE      any configuration key (repeatable), e.g. --set traffic.enabled=false
  --verbose            log debug events too
  --help               this text

Logs go to stderr, one line per event; the web view's address with its token is one of them.
SIGINT or SIGTERM stops it cleanly.
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
    config::apply_common_flags(args, config);
    if (auto v = args.value("dispatch")) config.settings.set("server.dispatch_policy", *v, "--dispatch");
    if (auto v = args.value("db")) config.settings.set("server.db_path", *v, "--db");
    if (args.flag("auto-orders")) config.settings.set("server.auto_orders", "true", "--auto-orders");
    if (auto v = args.value("http-port")) config.settings.set("server.http_port", *v, "--http-port");
    if (auto v = args.value("http-host")) config.settings.set("server.http_host", *v, "--http-host");
    const std::optional<std::string> token_flag = args.value("api-token");
    const bool verbose = args.flag("verbose");
    if (const auto rest = args.positionals(); !rest.empty()) throw ArgError("unexpected argument '" + rest[0] + "'");

    const std::string site_file = map::site_path(maps_dir(), config.settings.get_string("site"));
    // Loaded once, road network and graph included: dispatch costs and the web view use them.
    const auto site_map = std::make_shared<const map::SiteMap>(map::load_site_map(site_file));
    const map::Site& site = site_map->site;
    for (const auto& [fleet, robot] : config.all_robots()) {
      if (!site.find_home(robot->home)) {
        throw config::ConfigError(config.source + ": robot '" + robot->id + "': home '" + robot->home +
                                  "' is not a home of " + site_file);
      }
    }

    dds::use_fleet_dds_config();
    ProcessMemory::limit_arenas();
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);

    server::ServerOptions options;
    options.domain = static_cast<std::uint32_t>(config.settings.get_int("dds.domain"));
    options.time_scale = config.settings.get_double("time_scale");
    options.seed = static_cast<std::uint64_t>(config.settings.get_int("seed"));
    const std::filesystem::path db(config.settings.get_string("server.db_path"));
    options.db_path = (db.is_absolute() ? db : std::filesystem::path(project_root()) / db).string();
    options.config = std::move(config);
    options.site = site;
    options.site_map = site_map;
    // The maps robots can be switched to: the site and its revisions in maps/ (read once, for the
    // server loop and the web view).
    options.maps = map::site_revisions(site);
    auto log = make_logger("fleet-server", "", verbose ? spdlog::level::debug : spdlog::level::info);

    // The web view draws the site from its road network and graph; it and the server loop meet
    // only in the bridge.
    server::WebBridge bridge;
    // A copy: the server takes the options, the web view reads robots and fleets for as long as it runs.
    const config::FleetConfig web_config = options.config;
    std::unique_ptr<server::WebServer> web;
    const auto http_port = options.config.settings.get_int("server.http_port");
    if (http_port != 0) {
      server::WebOptions web_options;
      web_options.host = options.config.settings.get_string("server.http_host");
      web_options.port = static_cast<int>(http_port);
      web_options.stream_hz = options.config.settings.get_double("server.web_stream_hz");
      // Precedence: --api-token, then the environment, then the configuration file, then a fresh one.
      const char* env_token = std::getenv("FLEET_API_TOKEN");
      std::string token_source;
      if (token_flag && !token_flag->empty()) {
        web_options.token = *token_flag;
        token_source = "--api-token";
      } else if (env_token && *env_token) {
        web_options.token = env_token;
        token_source = "FLEET_API_TOKEN";
      } else if (const auto configured = options.config.settings.get_string("server.api_token"); !configured.empty()) {
        web_options.token = configured;
        token_source = "server.api_token";
      } else {
        web_options.token = server::generate_api_token();
        token_source = "generated";
      }
      server::WebSiteInfo info;
      info.site_map = site_map.get();
      info.config = &web_config;
      info.maps = options.maps;
      const std::string url = "http://" + web_options.host + ":" + std::to_string(web_options.port) + "/";
      const std::string token = web_options.token;
      web = std::make_unique<server::WebServer>(std::move(web_options), bridge, std::move(info), log);
      try {
        web->start();
        log->info("web view: {}?token={} (API token {}; from {})", url, token, token, token_source);
      } catch (const std::runtime_error& e) {
        // Orders and robots do not depend on the web view: a taken port costs the page, not the fleet.
        log->error("web view off: {}; choose another port with --http-port", e.what());
        web.reset();
      }
    }
    server::FleetServer fleet_server(std::move(options), log);
    if (web) fleet_server.attach_web(&bridge);
    fleet_server.run(g_stop);
    if (web) web->stop();
    return 0;
  } catch (const ArgError& e) {
    std::cerr << "fleet-server: " << e.what() << " (see --help)\n";
    return 2;
  } catch (const InputError& e) {
    std::cerr << "fleet-server: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "fleet-server: " << e.what() << "\n";
    return 1;
  }
}
