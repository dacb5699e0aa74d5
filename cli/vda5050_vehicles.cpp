#include "cli/vda5050_vehicles.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "common/args.hpp"
#include "common/paths.hpp"

namespace fleet::cli {

namespace {

/// A TCP port on 127.0.0.1 that nothing listens on now.
int free_loopback_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) throw std::runtime_error("no socket for a broker port");
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  socklen_t length = sizeof address;
  const bool ok = bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0 &&
                  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0;
  close(fd);
  if (!ok) throw std::runtime_error("no free port on 127.0.0.1 for the MQTT broker");
  return ntohs(address.sin_port);
}

bool accepts_connections(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return false;
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  close(fd);
  return ok;
}

std::string on_path(const std::string& program, const std::vector<std::string>& also) {
  std::vector<std::string> dirs = also;
  if (const char* path = std::getenv("PATH")) {
    std::istringstream parts(path);
    for (std::string dir; std::getline(parts, dir, ':');) dirs.push_back(dir);
  }
  for (const std::string& dir : dirs) {
    const std::filesystem::path candidate = std::filesystem::path(dir) / program;
    if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

}  // namespace

std::vector<std::pair<const config::FleetSpec*, const config::RobotSpec*>> pick_vda5050_vehicles(
    const config::FleetConfig& config, int count) {
  std::vector<std::pair<const config::FleetSpec*, const config::RobotSpec*>> picked;
  std::size_t declared = 0;
  for (const auto& fleet : config.fleets) {
    if (fleet.vda5050) declared += fleet.robots.size();
  }
  if (count > static_cast<int>(declared)) {
    throw ArgError("--vda5050-vehicles " + std::to_string(count) + ": " + config.source + " declares " +
                   std::to_string(declared) + " robots in fleets of robot type vda5050" +
                   (declared == 0 ? " (config/sites/table_a-vda5050.yaml declares some)" : ""));
  }
  for (std::size_t index = 0; static_cast<int>(picked.size()) < count; ++index) {
    for (const auto& fleet : config.fleets) {
      if (fleet.vda5050 && index < fleet.robots.size() && static_cast<int>(picked.size()) < count) {
        picked.emplace_back(&fleet, &fleet.robots[index]);
      }
    }
  }
  return picked;
}

std::string start_mqtt_broker(ProcessGroup& processes, const std::string& run_dir) {
  const std::string mosquitto = on_path("mosquitto", {"/usr/sbin"});
  if (mosquitto.empty()) throw std::runtime_error("an MQTT broker needs mosquitto (scripts/install-deps)");
  const int port = free_loopback_port();
  const std::string conf = run_dir + "/mosquitto.conf";
  std::ofstream(conf) << "# The run's own broker: loopback only, anonymous, in memory.\nlistener " << port
                      << " 127.0.0.1\nallow_anonymous true\npersistence false\n";
  processes.start("mosquitto", {mosquitto, "-c", conf}, run_dir + "/mosquitto.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!accepts_connections(port)) {
    if (std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error("mosquitto did not listen on 127.0.0.1:" + std::to_string(port) + " within 10 s; see " +
                               run_dir + "/mosquitto.log");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return "tcp://127.0.0.1:" + std::to_string(port);
}

Vda5050Vehicles start_vda5050_vehicles(ProcessGroup& processes, const config::FleetConfig& config,
                                       const map::Site& site, int count, double time_scale,
                                       std::vector<std::string> bridge_argv, const std::string& run_dir,
                                       const std::vector<std::string>& vehicle_args) {
  const auto picked = pick_vda5050_vehicles(config, count);
  const std::string node = on_path("node", {});
  const std::string script = project_root() + "/tests/vda5050/virtual_agvs.js";
  if (node.empty() || !std::filesystem::exists(project_root() + "/tests/vda5050/node_modules/vda-5050-lib")) {
    throw std::runtime_error("--vda5050-vehicles needs Node.js and tests/vda5050's packages (scripts/install-deps)");
  }

  Vda5050Vehicles out;
  out.broker = start_mqtt_broker(processes, run_dir);
  const std::string port = out.broker.substr(out.broker.rfind(':') + 1);
  bridge_argv.insert(bridge_argv.end(), {"--broker", out.broker, "--figures", run_dir + "/vda5050-figures.json"});
  processes.start("fleet-vda5050", bridge_argv, run_dir + "/fleet-vda5050.log");

  // One Node.js process per fleet: a fleet's vehicles share an interface name and a maker.
  std::map<const config::FleetSpec*, std::vector<std::string>> argv_of;
  for (const auto& [fleet, robot] : picked) {
    std::vector<std::string>& argv = argv_of[fleet];
    if (argv.empty()) {
      argv = {node, script, "--broker", "mqtt://127.0.0.1:" + port, "--interface", fleet->vda5050->interface_name,
              "--manufacturer", fleet->vda5050->manufacturer, "--speed", std::to_string(config.top_speed(*fleet)),
              "--time-lapse", std::to_string(time_scale),
              // Where it is between nodes five times a second (its state tells only at nodes).
              "--visualization-interval", "200"};
    }
    const map::Home* home = site.find_home(robot->home);
    if (home == nullptr) throw std::runtime_error("robot " + robot->id + ": home '" + robot->home + "' not on site");
    std::ostringstream vehicle;
    vehicle << robot->serial_number << ',' << home->pose.x << ',' << home->pose.y << ',' << home->pose.yaw << ','
            << site.name;
    argv.insert(argv.end(), {"--vehicle", vehicle.str()});
    out.robot_ids.push_back(robot->id);
  }
  for (auto& [fleet, argv] : argv_of) {
    argv.insert(argv.end(), vehicle_args.begin(), vehicle_args.end());
    processes.start("vda5050 vehicles " + fleet->id, argv, run_dir + "/vda5050-vehicles-" + fleet->id + ".log");
  }
  return out;
}

}  // namespace fleet::cli
