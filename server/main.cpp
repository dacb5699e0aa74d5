// fleet-server: orders, dispatch, fleet registry, site state and pose routing over DDS.

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include "app/process.hpp"
#include "common/errors.hpp"
#include "common/logging.hpp"
#include "common/paths.hpp"
#include "map/site_map.hpp"
#include "server/fleet_server.hpp"
#include "server/standby_mirror.hpp"
#include "server/web_server.hpp"

using namespace fleet;

namespace {

constexpr const char* kHelp = R"(usage: fleet-server [options]

The Fleet server: takes transport orders, dispatches them to robots, tracks robot health,
owns the site (map, static obstacles, pallets) and routes robot poses, all over Cyclone DDS.

options:
  --config FILE        configuration (default: config/fleet.yaml)
  --domain N           DDS domain id (default: dds.domain)
  --site NAME          site to serve: maps/NAME.yaml (default: site)
  --time-scale K       sim_time = K x wall time (default: time_scale)
  --seed S             seed of the random order generator (default: seed)
  --security DIR       join the DDS domain with DDS Security as 'server', with the credentials
                       of DIR (fleetctl security init; default: dds.security, empty: without)
  --dispatch POLICY    ascending-id | nearest | optimal (default: server.dispatch_policy)
  --db FILE            SQLite database of orders (default: server.db_path, fleet.db in the state folder)
  --auto-orders        create random orders whenever a robot is free
  --standby            start as a standby beside an active server: mirror its orders and site state
                       into this server's --db, take over when it is gone (server.standby); an
                       active server that hears another outrank it steps down to be its standby
  --http-port N        port of the web view and JSON API (default: server.http_port, 8080; 0: off)
  --http-host ADDR     address the web view binds (default: server.http_host, 127.0.0.1)
  --api-token TOKEN    the operator's token: every call of the web API (default: env
                       FLEET_API_TOKEN, else server.api_token, else one generated and logged)
  --viewer-token TOKEN the viewer's token: the page's reading calls and live stream (default:
                       env FLEET_VIEWER_TOKEN, else server.viewer_token, else generated, logged)
  --http-tls-cert PEM  serve the web view over HTTPS with this certificate (server.http_tls_cert;
  --http-tls-key PEM   with its key, server.http_tls_key; fleetctl security init writes a pair)
  --set KEY=VALUE      any configuration key (repeatable), e.g. --set traffic.enabled=false
  --verbose            log debug events too
  --help               this text

Logs go to stderr, one line per event; the web view's address with its token is one of them.
SIGINT or SIGTERM stops it cleanly.
)";

/// This process's name among the fleet's servers: server.id, else the host name and process id.
std::string server_id_of(const config::FleetConfig& config) {
  if (std::string id = config.settings.get_string("server.id"); !id.empty()) return id;
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0) std::snprintf(host, sizeof host, "host");
  return std::string(host) + "-" + std::to_string(getpid());
}

/// Where a web view token comes from: its flag, then the environment, then the configuration
/// file, else a fresh one.
struct TokenSource {
  std::optional<std::string> flag_value;
  const char* flag;
  const char* env;
  const char* key;
};

/// The token and where it came from.
std::pair<std::string, std::string> choose_token(const TokenSource& source, const config::FleetConfig& config) {
  const char* env_token = std::getenv(source.env);
  if (source.flag_value && !source.flag_value->empty()) return {*source.flag_value, source.flag};
  if (env_token && *env_token) return {env_token, source.env};
  if (const auto configured = config.settings.get_string(source.key); !configured.empty()) {
    return {configured, source.key};
  }
  return {server::generate_api_token(), "generated"};
}

/// The web view when server.http_port is not 0, started; nothing when it is off. A port that
/// cannot be bound (another server listens there) is an InputError naming it: a server whose
/// page and API answer at a URL that is not its own is worse than one that does not start.
/// The web view draws the site from its road network and graph; it and the server loop meet
/// only in `bridge`. `web_config` must outlive it.
std::unique_ptr<server::WebServer> start_web_view(const server::ServerOptions& options,
                                                  const config::FleetConfig& web_config,
                                                  const TokenSource& operator_source, const TokenSource& viewer_source,
                                                  server::WebBridge& bridge, const Logger& log) {
  const auto http_port = options.config.settings.get_int("server.http_port");
  if (http_port == 0) return nullptr;
  server::WebOptions web_options;
  web_options.host = options.config.settings.get_string("server.http_host");
  web_options.port = static_cast<int>(http_port);
  web_options.stream_hz = options.config.settings.get_double("server.web_stream_hz");
  const auto [token, token_source] = choose_token(operator_source, options.config);
  const auto [viewer, viewer_source_name] = choose_token(viewer_source, options.config);
  web_options.tokens = {viewer, token};
  web_options.tls_certificate = options.config.settings.get_string("server.http_tls_cert");
  web_options.tls_key = options.config.settings.get_string("server.http_tls_key");
  if (web_options.tls_certificate.empty() != web_options.tls_key.empty()) {
    throw InputError(
        "server.http_tls_cert and server.http_tls_key: HTTPS needs both (--http-tls-cert, --http-tls-key)");
  }
  if (viewer == token) {
    throw InputError("the viewer's token (from " + viewer_source_name + ") is the operator's (from " + token_source +
                     "): a viewer could change everything");
  }
  server::WebSiteInfo info;
  info.site_map = options.site_map.get();
  info.config = &web_config;
  info.maps = options.maps;
  const std::string url = std::string(web_options.tls_certificate.empty() ? "http" : "https") + "://" +
                          web_options.host + ":" + std::to_string(web_options.port) + "/";
  auto web = std::make_unique<server::WebServer>(std::move(web_options), bridge, std::move(info), log);
  try {
    web->start();
  } catch (const std::runtime_error& e) {
    throw InputError(std::string(e.what()) + "; choose another port with --http-port (0: no web view)");
  }
  log->info("web view: {}?token={} (the operator's token, from {}; the viewer's: {}?token={}, from {})", url, token,
            token_source, url, viewer, viewer_source_name);
  return web;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    Args args(argc, argv);
    auto config = app::read_config(args, kHelp, std::cout);
    if (!config) return 0;
    if (auto v = args.value("dispatch")) config->settings.set("server.dispatch_policy", *v, "--dispatch");
    if (auto v = args.value("db")) config->settings.set("server.db_path", *v, "--db");
    if (args.flag("auto-orders")) config->settings.set("server.auto_orders", "true", "--auto-orders");
    if (args.flag("standby")) config->settings.set("server.standby", "true", "--standby");
    if (auto v = args.value("http-port")) config->settings.set("server.http_port", *v, "--http-port");
    if (auto v = args.value("http-host")) config->settings.set("server.http_host", *v, "--http-host");
    if (auto v = args.value("http-tls-cert")) config->settings.set("server.http_tls_cert", *v, "--http-tls-cert");
    if (auto v = args.value("http-tls-key")) config->settings.set("server.http_tls_key", *v, "--http-tls-key");
    const TokenSource operator_source{args.value("api-token"), "--api-token", "FLEET_API_TOKEN", "server.api_token"};
    const TokenSource viewer_source{args.value("viewer-token"), "--viewer-token", "FLEET_VIEWER_TOKEN",
                                    "server.viewer_token"};
    const auto level = app::finish_args(args);

    std::vector<std::string> robots;
    for (const auto& [fleet, robot] : config->all_robots()) robots.push_back(robot->id);
    // Loaded once, road network and graph included: dispatch costs and the web view use them.
    const auto site_map = app::load_site(*config, robots);
    const std::atomic<bool>& stop = app::start_daemon();
    app::use_dds_security(config->settings.get_string("dds.security"), "server", "dds.security");

    server::ServerOptions options;
    app::set_run_options(options, *config);
    const std::filesystem::path db(config->settings.get_string("server.db_path"));
    options.db_path = (db.is_absolute() ? db : std::filesystem::path(state_dir()) / db).string();
    options.config = std::move(*config);
    options.site = site_map->site;
    options.site_map = site_map;
    // The maps robots can be switched to: the site and its revisions in maps/ (read once, for the
    // server loop and the web view).
    options.maps = map::site_revisions(options.site);
    auto log = make_logger("fleet-server", "", level);
    for (const std::string& warning : site_map->network.warnings) log->warn("road network: {}", warning);
    options.server_id = server_id_of(options.config);
    // A standby mirrors until the active server is gone, then serves; an active server that hears
    // another outrank it steps down and goes on as that one's standby.
    bool standby = options.config.settings.get_bool("server.standby");
    // A mirror that saw its active server die leaves DDS in the background: its writer lingers
    // for acknowledgements the dead server never sends (Cyclone's writer linger, 1 s), which
    // would hold up the takeover as long. Joined at the next takeover or at the end.
    std::jthread retiring;
    // What a server that steps down changed while cut off, for the active one to merge.
    std::vector<model::OrderInfo> handed_over;
    // One web view for the process: read-only while it stands by, the fleet's once it serves.
    server::WebBridge bridge;
    // A copy: the server takes the options, the web view reads robots and fleets for as long as it runs.
    const config::FleetConfig web_config = options.config;
    auto web = start_web_view(options, web_config, operator_source, viewer_source, bridge, log);
    for (;;) {
      if (standby) {
        auto mirror = std::make_unique<server::StandbyMirror>(options.domain, options.db_path, options.server_id, log);
        if (web) mirror->show_on(bridge, {options.site_map, &web_config, options.time_scale, options.server_id});
        if (!handed_over.empty()) mirror->hand_over(std::move(handed_over));
        handed_over.clear();
        if (!mirror->run_until_active_lost(stop, options.config.settings.get_double("server.standby_silence_s"))) {
          if (web) web->stop();
          return 0;
        }
        options.heard_term = mirror->heard_term();
        options.took_over = true;
        retiring = std::jthread([retired = std::move(mirror)]() mutable { retired.reset(); });
      }
      server::FleetServer fleet_server(options, log);
      if (web) fleet_server.attach_web(&bridge);
      const server::RunEnd end = fleet_server.run(stop);
      if (end == server::RunEnd::kStopped) {
        if (web) web->stop();
        return 0;
      }
      standby = true;
      handed_over = fleet_server.orders_to_hand_over();
    }
  } catch (...) {
    return app::exit_code_of_current_exception("fleet-server", std::cerr, true);
  }
}
