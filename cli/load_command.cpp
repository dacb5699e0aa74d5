// `fleetctl load`: a real fleet-server (dispatch, traffic, persistence and the web stream on)
// against N emulated robots on one DDS participant, with what the server's work costs per N.

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "cli/emulated_fleet.hpp"
#include "cli/fleet_run.hpp"
#include "cli/processes.hpp"
#include "common/clock.hpp"
#include "common/errors.hpp"
#include "common/paths.hpp"
#include "dds/qos.hpp"
#include "dds/security.hpp"
#include "map/site_map.hpp"
#include "model/names.hpp"
#include "robot/robot_factory.hpp"

namespace fleet::cli {

namespace {

struct LoadOptions {
  int robots = 50;
  std::string site;
  double duration_s = 120.0;  ///< wall seconds of the measured run
  double warmup_s = 10.0;     ///< wall seconds before it, while the robots register and set off
  double time_scale = 1.0;
  long seed = 1;
  std::string fleet_id;               ///< empty: the config's first fleet
  bool verbose = false;               ///< the server's debug log
  std::vector<std::string> settings;  ///< --set KEY=VALUE, for the server and the emulated robots
};

/// A port nobody listens on now, for the server's web view.
int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  const bool bound = fd >= 0 && bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
                     getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0;
  if (fd >= 0) close(fd);
  if (!bound) throw std::runtime_error("no free TCP port on 127.0.0.1 for the web view");
  return ntohs(address.sin_port);
}

/// One web view client on the server's event stream for the whole run, as a browser would hold
/// it: the server encodes and sends every frame. Counts the bytes it receives.
class StreamClient {
 public:
  StreamClient(int port, std::string token) {
    thread_ = std::thread([this, port, token = std::move(token)] {
      httplib::Client client("127.0.0.1", port);
      client.set_read_timeout(10, 0);
      const httplib::Headers headers{{"Authorization", "Bearer " + token}};
      while (!stop_) {
        client.Get("/api/stream", headers, [this](const char*, std::size_t n) {
          bytes_ += static_cast<double>(n);
          return !stop_.load();
        });
        if (!stop_) std::this_thread::sleep_for(std::chrono::milliseconds(200));
      }
    });
  }
  ~StreamClient() {
    stop_ = true;
    thread_.join();
  }
  double bytes() const { return bytes_.load(); }

 private:
  std::atomic<bool> stop_{false};
  std::atomic<double> bytes_{0.0};
  std::thread thread_;
};

/// The emulated fleet: the config's fleet `fleet_id` (or its first), its first `robots` robots
/// at their homes.
EmulatedFleetOptions fleet_options(const config::FleetConfig& config, const map::SiteMap& site,
                                   const LoadOptions& options, std::uint32_t domain) {
  const config::FleetSpec* fleet = &config.fleets.front();
  if (!options.fleet_id.empty()) {
    const auto it = std::find_if(config.fleets.begin(), config.fleets.end(),
                                 [&](const config::FleetSpec& f) { return f.id == options.fleet_id; });
    if (it == config.fleets.end()) {
      std::vector<std::string> ids;
      for (const auto& f : config.fleets) ids.push_back(f.id);
      throw ArgError("--fleet: " + model::unknown_name_message("fleet", options.fleet_id, ids));
    }
    fleet = &*it;
  }
  if (options.robots > static_cast<int>(fleet->robots.size())) {
    throw ArgError("--robots " + std::to_string(options.robots) + ": fleet '" + fleet->id + "' of " + config.source +
                   " declares " + std::to_string(fleet->robots.size()) + " robots; choose 1 .. " +
                   std::to_string(fleet->robots.size()));
  }
  EmulatedFleetOptions o;
  o.domain = domain;
  o.fleet_id = fleet->id;
  o.map_id = site.site.name;
  o.body = fleet->profile.footprint;
  o.params.speed = config.top_speed(*fleet);
  o.state_hz = config.settings.get_double("agent.state_hz");
  o.traffic_period_wall_s = 0.05 / options.time_scale;
  for (int i = 0; i < options.robots; ++i) {
    const config::RobotSpec& robot = fleet->robots[static_cast<std::size_t>(i)];
    o.robots.emplace_back(robot.id, site.site.find_home(robot.home)->pose);
  }
  return o;
}

double pct(double part, double whole) {
  return whole > 0.0 ? 100.0 * part / whole : 0.0;
}

/// The server's process, started with automatic orders, traffic, its database and the web view.
void start_server(ProcessGroup& processes, const CommandArgs& command, const LoadOptions& options, std::uint32_t domain,
                  const std::string& run_dir, int http_port, const std::string& token) {
  const std::string server_bin =
      (std::filesystem::read_symlink("/proc/self/exe").parent_path() / "fleet-server").string();
  std::vector<std::string> argv{server_bin,
                                "--config",
                                command.config_file,
                                "--domain",
                                std::to_string(domain),
                                "--site",
                                options.site,
                                "--time-scale",
                                std::to_string(options.time_scale),
                                "--seed",
                                std::to_string(options.seed),
                                "--auto-orders",
                                "--db",
                                run_dir + "/fleet.db",
                                "--http-port",
                                std::to_string(http_port),
                                "--api-token",
                                token,
                                "--set",
                                "traffic.enabled=true"};
  for (const auto& s : options.settings) argv.insert(argv.end(), {"--set", s});
  if (options.verbose) argv.push_back("--verbose");
  processes.start("fleet-server", argv, run_dir + "/fleet-server.log");
  FleetClient probe(domain);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!probe.find_server(std::chrono::milliseconds(200))) {
    if (!processes.reap().empty() || std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error("fleet-server did not start; see " + run_dir + "/fleet-server.log");
    }
  }
}

/// What one measured run gave.
struct LoadResult {
  double wall_s = 0.0;
  Usage server_start, server_end;
  double loopback_bytes = 0.0;
  double stream_bytes = 0.0;
  EmulatedFleetFigures start, end;
  model::ServerLoad server;
  std::string crashed;
};

nlohmann::json load_json(const LoadOptions& options, const LoadResult& r, bool ok) {
  const double wall = std::max(1e-9, r.wall_s);
  const auto ms = [](double s) { return round_to(s * 1e3, 0.01); };
  const auto per_s = [&](double v) { return round_to(v / wall, 1.0); };
  const EmulatedFleetFigures& f = r.end;
  return {
      {"robots", options.robots},
      {"site", options.site},
      {"time_scale", options.time_scale},
      {"measured_wall_s", round_to(r.wall_s, 0.1)},
      {"server_cpu_pct", round_to(pct(r.server_end.cpu_s - r.server_start.cpu_s, wall), 0.1)},
      {"server_rss_mb", round_to(r.server_end.rss_kb / 1024.0, 0.1)},
      {"server_peak_rss_mb", round_to(r.server_end.peak_rss_kb / 1024.0, 0.1)},
      {"robots_reported", r.server.robots},
      {"traffic_cycles", r.server.traffic_cycles},
      {"traffic_cycle_ms",
       {{"p50", round_to(r.server.traffic_cycle_p50_ms, 0.001)},
        {"p99", round_to(r.server.traffic_cycle_p99_ms, 0.001)},
        {"max", round_to(r.server.traffic_cycle_max_ms, 0.001)}}},
      {"traffic_update_ms",
       {{"p50", round_to(r.server.traffic_update_p50_ms, 0.001)},
        {"p99", round_to(r.server.traffic_update_p99_ms, 0.001)},
        {"max", round_to(r.server.traffic_update_max_ms, 0.001)}}},
      {"dispatches", r.server.dispatches},
      {"dispatch_ms",
       {{"p50", round_to(r.server.dispatch_p50_ms, 0.001)},
        {"p99", round_to(r.server.dispatch_p99_ms, 0.001)},
        {"max", round_to(r.server.dispatch_max_ms, 0.001)}}},
      {"grant_latency_ms",
       {{"p50", ms(f.grant_latency.p50_s)}, {"p99", ms(f.grant_latency.p99_s)}, {"max", ms(f.grant_latency.max_s)}}},
      {"routes_sent", f.routes_sent - r.start.routes_sent},
      {"routes_answered_late", f.routes_answered_late - r.start.routes_answered_late},
      {"routes_unanswered", f.routes_unanswered},
      {"loopback_bytes_per_s", per_s(r.loopback_bytes)},
      {"samples_to_server_per_s", per_s(static_cast<double>(f.samples_out - r.start.samples_out))},
      {"samples_from_server_per_s", per_s(static_cast<double>(f.samples_in - r.start.samples_in))},
      {"web_stream_bytes_per_s", per_s(r.stream_bytes)},
      {"orders_done", f.orders_done - r.start.orders_done},
      {"orders_done_per_sim_min", round_to(static_cast<double>(f.orders_done - r.start.orders_done) /
                                               std::max(1e-9, wall * options.time_scale / 60.0),
                                           0.1)},
      {"orders_rejected", f.orders_rejected},
      {"collisions", f.collisions},
      {"deadlocks", f.deadlocks},
      {"max_wait_s", round_to(f.max_wait_s, 0.1)},
      {"crashed", r.crashed},
      {"ok", ok}};
}

void print_load(std::ostream& out, const nlohmann::json& j) {
  const auto& t = j["traffic_cycle_ms"];
  const auto& u = j["traffic_update_ms"];
  const auto& d = j["dispatch_ms"];
  const auto& g = j["grant_latency_ms"];
  out << "load: " << j["robots"] << " emulated robots on " << j["site"].get<std::string>() << ", "
      << j["measured_wall_s"] << " s wall measured\n"
      << "  server: " << j["server_cpu_pct"] << " % of a core, " << j["server_rss_mb"] << " MB resident\n"
      << "  traffic cycle: p50 " << t["p50"] << " ms, p99 " << t["p99"] << " ms, max " << t["max"] << " ms ("
      << j["traffic_cycles"] << " cycles: the requests since the last one, then the update)\n"
      << "  traffic update (every robot's grant decided): p50 " << u["p50"] << " ms, p99 " << u["p99"] << " ms, max "
      << u["max"] << " ms\n"
      << "  dispatch: p50 " << d["p50"] << " ms, p99 " << d["p99"] << " ms (" << j["dispatches"] << " rounds)\n"
      << "  first grant of a new route: p50 " << g["p50"] << " ms, p99 " << g["p99"] << " ms, max " << g["max"]
      << " ms; " << j["routes_answered_late"] << " of " << j["routes_sent"] << " later than two cycles, "
      << j["routes_unanswered"] << " unanswered\n"
      << "  wire: " << j["loopback_bytes_per_s"] << " B/s on loopback; " << j["samples_to_server_per_s"]
      << " samples/s to the server, " << j["samples_from_server_per_s"] << " from it; web stream "
      << j["web_stream_bytes_per_s"] << " B/s\n"
      << "  orders: " << j["orders_done"] << " done (" << j["orders_done_per_sim_min"] << " per sim minute), "
      << j["orders_rejected"] << " rejected\n"
      << "  collisions " << j["collisions"] << ", deadlocks " << j["deadlocks"] << ", longest wait " << j["max_wait_s"]
      << " s\n";
}

/// Runs the emulated fleet against the server: the warm-up, then the measured part.
LoadResult run_load(const LoadOptions& options, ProcessGroup& processes, EmulatedFleet& emulated, StreamClient& stream,
                    std::uint32_t domain) {
  FleetClient client(domain);
  dds::Reader<model::ServerLoad> load_reader(client.participant(), dds::qos::live_state());
  SimClock clock(options.time_scale);
  const pid_t server_pid = processes.children().front().pid;
  LoadResult r;
  std::optional<Usage> usage_start;
  double lo_start = 0.0, stream_start = 0.0, wall_start = 0.0;
  const double t0 = SimClock::wall_now();
  while (!stop_requested()) {
    const double now_wall = SimClock::wall_now();
    emulated.run_until(clock.now());
    load_reader.take_data([&](model::ServerLoad&& l) {
      if (l.active) r.server = std::move(l);
    });
    if (!processes.reap().empty()) {
      r.crashed = "fleet-server " + ProcessGroup::describe(processes.children().front().exit_status);
      break;
    }
    if (!usage_start && now_wall - t0 >= options.warmup_s) {
      usage_start = usage_of(server_pid);
      lo_start = loopback_bytes().value_or(0.0);
      stream_start = stream.bytes();
      wall_start = now_wall;
      r.start = emulated.figures();
      emulated.restart_latency();
    }
    if (usage_start && now_wall - wall_start >= options.duration_s) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  r.wall_s = SimClock::wall_now() - wall_start;
  const auto usage_end = usage_of(server_pid);
  if (!usage_start || !usage_end) {
    throw std::runtime_error(r.crashed.empty() ? "stopped before the measured part began" : r.crashed);
  }
  r.server_start = *usage_start;
  r.server_end = *usage_end;
  r.loopback_bytes = loopback_bytes().value_or(0.0) - lo_start;
  r.stream_bytes = stream.bytes() - stream_start;
  r.end = emulated.figures();
  return r;
}

}  // namespace

int load_command(const CommandArgs& command, std::ostream& out, std::ostream& err, std::uint32_t domain) {
  const CommandFlags args("load", "", command.args);
  if (!dds::security_folder().empty()) {
    // Its emulated robots write for many robots from one participant, which DDS Security's
    // per-robot partitions do not grant.
    throw InputError("--security: fleetctl load does not run on a domain with DDS Security; run it without");
  }
  config::FleetConfig config = config::load_fleet_config(command.config_file);
  LoadOptions options;
  options.robots = static_cast<int>(args.integer("robots").value_or(50));
  options.site = args.value("site").value_or(config.settings.get_string("site"));
  options.duration_s = args.number("duration").value_or(120.0);
  options.warmup_s = args.number("warmup").value_or(10.0);
  options.time_scale = args.number("time-scale").value_or(1.0);
  options.seed = args.integer("seed").value_or(config.settings.get_int("seed"));
  options.fleet_id = args.value("fleet").value_or("");
  options.verbose = args.flag("verbose");
  options.settings = args.values("set");
  // Checked here, named as given, before any process starts.
  for (const auto& s : options.settings) config::apply_set_flag(config, s);
  known_site_path(command.source_dir, options.site);
  {
    FleetClient probe(domain);
    if (probe.find_server(std::chrono::milliseconds(1200))) {
      throw ArgError("a fleet-server already runs on DDS domain " + std::to_string(domain) +
                     "; stop it or choose another --domain");
    }
  }
  const auto site = std::make_shared<const map::SiteMap>(map::load_site_map(map::site_path(maps_dir(), options.site)));
  std::vector<std::string> homes;
  for (const auto& h : site->site.homes) homes.push_back(h.id);
  config::assign_homes(config, homes, site->site.name);
  const EmulatedFleetOptions fleet_opts = fleet_options(config, *site, options, domain);
  const config::FleetSpec& fleet = *config.find_robot(fleet_opts.robots.front().first)->first;

  install_stop_handlers();
  auto log = make_logger("fleetctl load", "", options.verbose ? spdlog::level::debug : spdlog::level::info);
  const std::string run_dir =
      state_dir() + "/runs/load-" + std::to_string(options.robots) + "-" + std::to_string(getpid());
  std::filesystem::create_directories(run_dir);
  const int http_port = free_port();
  const std::string token = random_token();
  ProcessGroup processes;
  start_server(processes, command, options, domain, run_dir, http_port, token);
  err << "fleetctl load: fleet-server and " << options.robots << " emulated robots of fleet '" << fleet.id
      << "' (a load generator: kinematic bodies, exact poses, no sensors) on site " << options.site << ", time scale "
      << options.time_scale << "; " << options.warmup_s << " s warm-up, then " << options.duration_s
      << " s measured. Logs: " << run_dir << "/\n";
  LoadResult result;
  {
    EmulatedFleet emulated(fleet_opts, robot::route_graph_for(config, fleet, *site), log);
    StreamClient stream(http_port, token);
    result = run_load(options, processes, emulated, stream, domain);
  }
  processes.stop_all();
  const EmulatedFleetFigures& f = result.end;
  const bool ok =
      result.crashed.empty() && f.collisions == 0 && f.deadlocks == 0 && result.server.robots == options.robots;
  nlohmann::json j = load_json(options, result, ok);
  j["run_dir"] = run_dir;
  if (command.json) {
    out << j.dump() << "\n";
  } else {
    print_load(out, j);
  }
  if (!result.crashed.empty())
    err << "fleetctl load: " << result.crashed << "; see " << run_dir << "/fleet-server.log\n";
  return ok ? kExitOk : kExitFailed;
}

}  // namespace fleet::cli
