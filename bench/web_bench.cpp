// The web view under load: N synthetic robots published at 20 Hz into a WebBridge,
// streamed to M server-sent-event clients. Measures the CPU time of the web server's threads
// (the process's CPU time minus the synthetic publisher's), as a share of one core. The clients
// run in a child process so that their parsing is not counted.
//
//   web_bench [--robots 50] [--clients 4] [--seconds 10] [--hz 20] [--port 18099] [--replan-every 100]
//   web_bench --serve [--seconds 60] ...     serves the page with the synthetic robots, for
//                                            tests/web/fps_bench.js (the page's frame rate)
//
// Prints one JSON line. Never asserts a time: it reports.

#include <httplib.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "common/args.hpp"
#include "common/logging.hpp"
#include "config/fleet_config.hpp"
#include "map/site_map.hpp"
#include "server/web_bridge.hpp"
#include "server/web_server.hpp"

namespace {

using namespace fleet;

struct Options {
  int robots = 50;
  int clients = 4;
  double seconds = 10.0;
  double hz = 20.0;
  int port = 18099;
  int replan_every = 100;  ///< frames between a robot's new paths
  bool serve = false;
  bool client_only = false;
};

Options parse(int argc, char** argv) {
  constexpr long kIntMax = std::numeric_limits<int>::max();
  constexpr double kAny = std::numeric_limits<double>::max();
  Args args(argc, argv);
  Options o;
  o.robots = static_cast<int>(args.integer("robots", 0, kIntMax).value_or(o.robots));
  o.clients = static_cast<int>(args.integer("clients", 0, kIntMax).value_or(o.clients));
  o.seconds = args.number("seconds", -kAny, kAny).value_or(o.seconds);
  o.hz = args.number("hz", -kAny, kAny).value_or(o.hz);
  o.port = static_cast<int>(args.integer("port", 0, 65535).value_or(o.port));
  o.replan_every = static_cast<int>(args.integer("replan-every", 0, kIntMax).value_or(o.replan_every));
  o.serve = args.flag("serve");
  o.client_only = args.flag("client-only");
  if (const auto rest = args.positionals(); !rest.empty()) throw ArgError("unknown argument " + rest.front());
  return o;
}

double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double process_cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
  return s(u.ru_utime) + s(u.ru_stime);
}

/// "r<i>"; appended rather than `"r" + std::to_string(i)`, which trips GCC 12's -Wrestrict false
/// positive at -O3.
std::string robot_name(std::size_t i) {
  return std::string("r").append(std::to_string(i));
}

/// Robots driving round the road graph, each with its next 40 graph points as its path, plus 20
/// open and 50 ended orders with histories: about what a busy 50-robot site publishes.
class SyntheticFleet {
 public:
  SyntheticFleet(const map::SiteMap& site, int robots, int replan_every)
      : site_(site), replan_every_(std::max(1, replan_every)), paths_(static_cast<std::size_t>(robots)) {
    const auto& graph = site.graph.graph;
    for (int i = 0; i < robots; ++i) at_.push_back(static_cast<int>((graph.points.size() * i) / robots));
    for (int i = 0; i < 70; ++i) {
      model::OrderInfo o;
      o.order_id = i + 1;
      o.pick_area = std::string("A1");
      o.drop_area = std::string("A2");
      o.robot_id = robot_name(static_cast<std::size_t>(i % robots));
      o.state = std::string(i < 50 ? "DONE" : "ACTIVE");
      o.phase = std::string(i < 50 ? "DROPPING" : "TO_PICK");
      for (int e = 0; e < 10; ++e) {
        model::OrderEvent event;
        event.sim_time = e;
        event.state = o.state;
        event.phase = o.phase;
        event.robot_id = o.robot_id;
        o.history.push_back(std::move(event));
      }
      orders_.push_back(std::move(o));
    }
  }

  server::LiveSnapshot step(double t) {
    const auto& graph = site_.graph.graph;
    server::LiveSnapshot s;
    s.sim_time = t;
    s.time_scale = 1.0;
    for (std::size_t i = 0; i < at_.size(); ++i) {
      // One graph point per frame: 0.1 m at 20 Hz is 2 m/s, every robot moves every frame.
      const auto& succ = graph.successors[static_cast<std::size_t>(at_[i])];
      if (!succ.empty()) at_[i] = succ[i % succ.size()];
      const auto& p = graph.points[static_cast<std::size_t>(at_[i])];
      server::RobotView v;
      v.state.robot_id = robot_name(i);
      v.state.fleet_id = "forklifts";
      v.state.map_id = site_.site.name;
      v.state.pose = {p.x, p.y, std::fmod(t + static_cast<double>(i), 6.28) - 3.14};
      v.state.covariance = {1e-4, 1e-5, 0, 1e-5, 2e-4, 0, 0, 0, 1e-3};
      v.state.task_state = "TRACK_PATH";
      v.state.sim_time = t;
      v.truth = model::SimTruth{v.state.robot_id, v.state.pose, {}, false, t};
      v.health = "alive";
      // Agents publish a path when they plan, not every frame: here each robot replans every
      // 100 frames (5 s at 20 Hz), staggered; `--replan-every 1` gives the worst case.
      if (paths_[i].empty() || (frame_ + i) % static_cast<std::size_t>(replan_every_) == 0)
        paths_[i] = path_from(at_[i]);
      v.path = paths_[i];
      s.robots.push_back(std::move(v));
    }
    ++frame_;
    s.orders = orders_;
    for (const auto& o : site_.site.static_obstacles) s.obstacle_enabled[o.id] = false;
    for (const auto& a : site_.site.loading_areas) s.pallet_at[a.id] = a.pallet_at_start;
    return s;
  }

 private:
  std::vector<geometry::Vec2> path_from(int k) const {
    const auto& graph = site_.graph.graph;
    std::vector<geometry::Vec2> path;
    for (int n = 0; n < 40; ++n) {
      const auto& q = graph.points[static_cast<std::size_t>(k)];
      path.push_back({q.x, q.y});
      const auto& next = graph.successors[static_cast<std::size_t>(k)];
      if (next.empty()) break;
      k = next.front();
    }
    return path;
  }

  const map::SiteMap& site_;
  int replan_every_;
  std::size_t frame_ = 0;
  std::vector<int> at_;
  std::vector<std::vector<geometry::Vec2>> paths_;
  std::vector<model::OrderInfo> orders_;
};

/// The child: M stream clients that count what they receive.
int run_clients(const Options& o) {
  std::atomic<long> bytes{0}, events{0};
  std::atomic<bool> stop{false};
  std::vector<std::thread> threads;
  for (int c = 0; c < o.clients; ++c) {
    threads.emplace_back([&] {
      httplib::Client http("127.0.0.1", o.port);
      http.set_read_timeout(10, 0);
      http.Get("/api/stream", {{"Authorization", "Bearer bench"}}, [&](const char* data, std::size_t n) {
        bytes += static_cast<long>(n);
        for (std::size_t i = 0; i + 1 < n; ++i) {
          if (data[i] == '\n' && data[i + 1] == '\n') ++events;
        }
        return !stop.load();
      });
    });
  }
  std::this_thread::sleep_for(std::chrono::duration<double>(o.seconds));
  stop = true;
  for (auto& t : threads) t.join();
  std::printf("%ld %ld\n", bytes.load(), events.load());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  try {
    o = parse(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "web_bench: " << e.what() << "\n";
    return 2;
  }
  if (o.client_only) return run_clients(o);

  const auto site = map::load_site_map_unchecked(std::string(FLEET_SOURCE_DIR) + "/maps/table_a.yaml");
  const auto config = config::load_fleet_config(std::string(FLEET_SOURCE_DIR) + "/config/fleet.yaml");
  server::WebBridge bridge;
  server::WebOptions web_options;
  web_options.port = o.port;
  web_options.tokens = {"bench-viewer", "bench"};
  web_options.stream_hz = o.hz;
  web_options.max_stream_clients = std::max(32, o.clients + 4);
  auto log = make_logger("web_bench", "", spdlog::level::warn);
  server::WebServer web(web_options, bridge, {&site, &config, {site.site.name}}, log);
  web.start();

  // The server loop's part: build and publish snapshots. Its CPU time is not the web's.
  std::atomic<bool> stop{false};
  std::atomic<double> publisher_cpu{0.0};
  std::thread publisher([&] {
    SyntheticFleet fleet(site, o.robots, o.replan_every);
    const auto period = std::chrono::duration<double>(1.0 / o.hz);
    auto next = std::chrono::steady_clock::now();
    double t = 0.0;
    while (!stop) {
      bridge.publish(fleet.step(t));
      t += 1.0 / o.hz;
      publisher_cpu = thread_cpu_s();
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
      std::this_thread::sleep_until(next);
    }
  });

  if (o.serve) {
    std::cerr << "web_bench: serving " << o.robots << " robots at http://127.0.0.1:" << web.port()
              << "/?token=bench for " << o.seconds << " s\n";
    std::this_thread::sleep_for(std::chrono::duration<double>(o.seconds));
    stop = true;
    publisher.join();
    return 0;
  }

  // Clients in a child process, for warm-up plus the measured window.
  const double warmup = 2.0;
  int pipe_fd[2];
  if (pipe(pipe_fd) != 0) return 1;
  // Arguments built before fork: the child of a threaded process only calls exec.
  const std::string clients_arg = std::to_string(o.clients);
  const std::string port_arg = std::to_string(web.port());
  const std::string seconds_arg = std::to_string(o.seconds + warmup);
  const pid_t child = fork();
  if (child == 0) {
    dup2(pipe_fd[1], STDOUT_FILENO);
    close(pipe_fd[0]);
    execl("/proc/self/exe", argv[0], "--client-only", "--clients", clients_arg.c_str(), "--port", port_arg.c_str(),
          "--seconds", seconds_arg.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  close(pipe_fd[1]);
  std::this_thread::sleep_for(std::chrono::duration<double>(warmup));
  const double cpu0 = process_cpu_s();
  const double pub0 = publisher_cpu.load();
  const auto frames0 = web.frames_built();
  const auto wall0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(o.seconds));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double cpu = process_cpu_s() - cpu0;
  const double pub = publisher_cpu.load() - pub0;
  const auto frames = web.frames_built() - frames0;

  char buf[128] = {};
  const auto n = read(pipe_fd[0], buf, sizeof buf - 1);
  int status = 0;
  waitpid(child, &status, 0);
  long bytes = 0, events = 0;
  if (n > 0) std::sscanf(buf, "%ld %ld", &bytes, &events);
  stop = true;
  publisher.join();
  web.stop();

  const double web_cpu = cpu - pub;
  std::printf(
      "{\"robots\": %d, \"clients\": %d, \"hz\": %.0f, \"seconds\": %.1f, \"frames_built_per_s\": %.1f, "
      "\"web_cpu_percent_of_one_core\": %.2f, \"publisher_cpu_percent\": %.2f, \"stream_bytes_per_client_per_s\": "
      "%.0f, "
      "\"events_per_client_per_s\": %.1f}\n",
      o.robots, o.clients, o.hz, wall, static_cast<double>(frames) / wall, 100.0 * web_cpu / wall, 100.0 * pub / wall,
      o.clients > 0 ? static_cast<double>(bytes) / (o.seconds + warmup) / o.clients : 0.0,
      o.clients > 0 ? static_cast<double>(events) / (o.seconds + warmup) / o.clients : 0.0);
  return 0;
}
