#include "vda5050_bridge/bridge.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <thread>

#include "common/clock.hpp"
#include "common/percentile.hpp"
#include "dds/qos.hpp"
#include "orders/order_kind.hpp"
#include "robot/robot_factory.hpp"
#include "robot/traffic_follower.hpp"

namespace fleet::vda5050_bridge {

using nlohmann::json;

namespace {

/// Wall seconds between the bridge's cycles: a grant waits for the next cycle to be passed on.
constexpr double kCycleWall = 0.02;
/// A vehicle's bad messages are logged at most once a minute each.
constexpr double kBadMessageLogEvery = 60.0;
/// Grant-to-broker latencies kept for the figures at most.
constexpr std::size_t kLatencySamples = 1000000;
/// Wall seconds between the figures in the log.
constexpr double kFiguresLogEvery = 60.0;

double cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

std::string topic_prefix(const vda5050::VehicleAddress& a) {
  std::string out = vda5050::topic(a, "");
  return out;
}

/// The partitions of the VDA 5050 vehicles of `config`, one per robot.
std::vector<std::string> vehicle_partitions(const config::FleetConfig& config) {
  std::vector<std::string> partitions;
  for (const auto& [fleet, robot] : config.all_robots()) {
    if (fleet->vda5050) partitions.push_back(model::robot_partition(robot->id));
  }
  return partitions;
}

}  // namespace

Bridge::Bridge(BridgeOptions options, Logger log)
    : options_(std::move(options)),
      log_(std::move(log)),
      participant_(options_.domain),
      state_writer_(participant_, dds::qos::robot_state()),
      report_writer_(participant_, dds::qos::latched_state()),
      path_writer_(participant_, dds::qos::live_state()),
      traffic_writer_(participant_, dds::qos::live_state()),
      truth_writer_(participant_, dds::qos::live_state()),
      grant_reader_(participant_, dds::qos::live_state(), vehicle_partitions(options_.config)),
      order_reader_(participant_, dds::qos::latched_state()),
      pallet_reader_(participant_, dds::qos::latched_state()),
      control_reader_(participant_, dds::qos::latched_state()) {
  const std::uint64_t first_version = robot::first_route_version(std::chrono::system_clock::now());
  std::vector<std::string> subscriptions;
  for (const config::FleetSpec& fleet : options_.config.fleets) {
    if (!fleet.vda5050) continue;
    auto routes =
        std::make_shared<emulation::EmulatedRoutes>(robot::route_graph_for(options_.config, fleet, *options_.site));
    const vda5050::VehicleAddress any{fleet.vda5050->interface_name, fleet.vda5050->version,
                                      fleet.vda5050->manufacturer, "+"};
    for (const char* name : {"state", "visualization", "connection", "factsheet"})
      subscriptions.push_back(vda5050::topic(any, name));
    for (const config::RobotSpec& robot : fleet.robots) {
      const map::Home* home = options_.site->site.find_home(robot.home);
      if (home == nullptr) {
        throw config::ConfigError(options_.config.source + ": robot " + robot.id + ": home '" + robot.home +
                                  "' is not a home of site '" + options_.site->site.name + "'");
      }
      Vehicle v;
      v.fleet = &fleet;
      v.address = {fleet.vda5050->interface_name, fleet.vda5050->version, fleet.vda5050->manufacturer,
                   robot.serial_number};
      v.master = std::make_unique<vda5050::VehicleMaster>(robot.id, fleet.vda5050->version, options_.site->site.name,
                                                          robot.home, home->pose, first_version);
      v.routes = routes;
      // The vehicle's writers exist before its first sample, matched with their readers by then.
      const std::string partition = model::robot_partition(robot.id);
      state_writer_.open(partition);
      report_writer_.open(partition);
      path_writer_.open(partition);
      traffic_writer_.open(partition);
      truth_writer_.open(partition);
      by_robot_[robot.id] = vehicles_.size();
      by_topic_prefix_[topic_prefix(v.address)] = vehicles_.size();
      vehicles_.push_back(std::move(v));
    }
  }
  if (vehicles_.empty()) {
    throw config::ConfigError(options_.config.source +
                              " declares no fleet of robot type vda5050: fleet-vda5050 has no vehicle to drive");
  }
  std::sort(subscriptions.begin(), subscriptions.end());
  subscriptions.erase(std::unique(subscriptions.begin(), subscriptions.end()), subscriptions.end());
  mqtt_ = std::make_unique<mqtt_link::MqttLink>(options_.broker, "fleet-vda5050-" + std::to_string(getpid()),
                                                subscriptions);
  log_->info("master of {} VDA 5050 vehicles on {}", vehicles_.size(), options_.broker);
}

void Bridge::run(const std::atomic<bool>& stop) {
  SimClock clock(options_.time_scale);
  bool was_connected = false;
  started_wall_ = SimClock::wall_now();
  double next_figures = started_wall_ + kFiguresLogEvery;
  while (!stop) {
    if (SimClock::wall_now() >= next_figures) {
      next_figures += kFiguresLogEvery;
      log_->info("figures: {}", figures().dump());
    }
    const bool connected = mqtt_->connected();
    if (connected != was_connected) {
      if (connected) {
        log_->info("connected to the MQTT broker {}", options_.broker);
      } else {
        log_->warn("lost the MQTT broker {}; reconnecting", options_.broker);
      }
      was_connected = connected;
    }
    cycle(SimClock::wall_now(), clock.now());
    std::this_thread::sleep_for(std::chrono::duration<double>(kCycleWall));
  }
  const nlohmann::json f = figures();
  log_->info("figures: {}", f.dump());
  if (!options_.figures_file.empty()) std::ofstream(options_.figures_file) << f.dump(2) << "\n";
}

nlohmann::json Bridge::figures() const {
  std::vector<double> latencies;
  {
    std::lock_guard lock(latency_mutex_);
    latencies = grant_to_broker_s_;
  }
  const double wall = std::max(1e-9, SimClock::wall_now() - started_wall_);
  const double cpu_pct = 100.0 * cpu_seconds() / wall;
  const auto ms = [&](double q) {
    return latencies.empty() ? 0.0 : std::round(common::percentile(latencies, q) * 1e5) / 100.0;
  };
  // The vehicles it drove: a configuration may declare more than there are on the broker.
  const auto driven = std::max<std::size_t>(
      1, std::count_if(vehicles_.begin(), vehicles_.end(), [](const Vehicle& v) { return v.online || v.was_lost; }));
  return {{"vehicles", driven},
          {"vehicles_declared", vehicles_.size()},
          {"wall_s", std::round(wall * 10.0) / 10.0},
          {"cpu_pct", std::round(cpu_pct * 100.0) / 100.0},
          {"cpu_pct_per_vehicle", std::round(cpu_pct / static_cast<double>(driven) * 1000.0) / 1000.0},
          {"order_updates_timed", latencies.size()},
          {"grant_to_broker_p50_ms", ms(0.5)},
          {"grant_to_broker_p95_ms", ms(0.95)},
          {"grant_to_broker_max_ms", ms(1.0)}};
}

void Bridge::cycle(double now_wall, double now_sim) {
  take_mqtt(now_wall);
  take_pallets();
  take_controls();
  take_orders(now_sim);
  take_grants();
  for (Vehicle& v : vehicles_) {
    watch_liveness(v, now_wall);
    if (!v.online) continue;
    v.master->step(*v.routes);
    send(v, now_wall);
    for (const vda5050::MasterEvent& e : v.master->take_events()) {
      using K = vda5050::MasterEvent::Kind;
      if (e.kind == K::kPhase) {
        v.phase = e.phase;
        report(v, e.phase, now_sim);
      } else if (e.kind == K::kDone) {
        report(v, "DONE", now_sim, e.load_id, e.load_pose);
        v.order_id = 0;
        v.phase.clear();
      } else {
        log_->warn("{}: order {} failed: {}", v.master->id(), e.order_id, e.reason);
        report(v, "FAILED", now_sim, -1, {}, e.reason);
        v.order_id = 0;
        v.phase.clear();
      }
    }
    publish(v, now_sim);
  }
}

void Bridge::take_mqtt(double now_wall) {
  for (mqtt_link::MqttMessage& m : mqtt_->take()) {
    const auto slash = m.topic.rfind('/');
    if (slash == std::string::npos) continue;
    const std::string prefix = m.topic.substr(0, slash + 1);
    const std::string kind = m.topic.substr(slash + 1);
    const auto found = by_topic_prefix_.find(prefix);
    if (found == by_topic_prefix_.end()) {
      // Reported once: a vehicle on the broker that no fleet declares.
      if (unknown_reported_.emplace(prefix, now_wall).second) {
        log_->warn(
            "a vehicle no fleet declares speaks on {}: ignored (add its serial number to a fleet of robot "
            "type vda5050)",
            m.topic);
      }
      continue;
    }
    take_message(vehicles_[found->second], kind, m.payload, now_wall);
  }
}

void Bridge::take_message(Vehicle& v, const std::string& kind, const std::string& payload, double now_wall) {
  try {
    const json message = json::parse(payload);
    if (kind == "state") {
      v.master->take_state(vda5050::parse_state(message));
      v.last_state_wall = now_wall;
      v.state_requested = false;
    } else if (kind == "visualization") {
      vda5050::VehicleState position;
      if (vda5050::read_visualization(message, position)) v.master->take_position(position);
    } else if (kind == "factsheet") {
      check_factsheet(v, message);
    } else if (kind == "connection") {
      v.connection = vda5050::parse_connection(message);
      log_->info("{} ({}): connection {}", v.master->id(), v.address.serial_number, v.connection);
    }
  } catch (const std::exception& e) {
    if (now_wall >= v.next_bad_message_log) {
      v.next_bad_message_log = now_wall + kBadMessageLogEvery;
      log_->warn("{}: ignoring a message on {}: {} (logged once a minute)", v.master->id(),
                 vda5050::topic(v.address, kind), e.what());
    }
  }
}

void Bridge::check_factsheet(Vehicle& v, const json& message) {
  const std::string text = message.dump();
  if (text == v.factsheet) return;
  v.factsheet = text;
  const config::FleetSpec& fleet = *v.fleet;
  const auto differences = vda5050::factsheet_differences(vda5050::parse_factsheet(message), fleet.footprint.length,
                                                          fleet.footprint.width, fleet.profile.max_speed);
  if (differences.empty()) {
    log_->info("{} ({}): its factsheet agrees with fleet {}'s profile", v.master->id(), v.address.serial_number,
               fleet.id);
    return;
  }
  std::string joined;
  for (const std::string& d : differences) joined += (joined.empty() ? "" : "; ") + d;
  log_->warn("{} ({}): {}; Fleet plans with fleet {}'s profile ({})", v.master->id(), v.address.serial_number, joined,
             fleet.id, options_.config.source);
}

void Bridge::watch_liveness(Vehicle& v, double now_wall) {
  // Silent for half its timeout: ask for its state once before counting it lost.
  if (v.online && !v.state_requested && now_wall - v.last_state_wall > 0.5 * options_.state_timeout_s) {
    v.state_requested = true;
    v.master->request("stateRequest");
  }
  const bool fresh = v.last_state_wall >= 0.0 && now_wall - v.last_state_wall <= options_.state_timeout_s;
  const bool alive = fresh && v.connection != "OFFLINE" && v.connection != "CONNECTIONBROKEN" && mqtt_->connected() &&
                     v.master->has_state();
  if (alive == v.online) return;
  v.online = alive;
  if (alive) {
    log_->info("{} ({}) is online{}", v.master->id(), v.address.serial_number, v.was_lost ? " again" : "");
    if (v.was_lost) v.master->reconnected();
    v.master->request("factsheetRequest");
    return;
  }
  v.was_lost = true;
  std::string why = "no state for " + std::to_string(static_cast<int>(now_wall - v.last_state_wall)) + " s";
  if (!mqtt_->connected()) why = "the MQTT broker is gone";
  if (v.connection == "OFFLINE" || v.connection == "CONNECTIONBROKEN") why = "connection " + v.connection;
  log_->warn("{} ({}) is lost: {}", v.master->id(), v.address.serial_number, why);
  // The server counts it lost at once: its RobotState instance is gone.
  model::RobotState gone;
  gone.robot_id = v.master->id();
  state_writer_.open(model::robot_partition(gone.robot_id)).unregister(gone);
}

void Bridge::send(Vehicle& v, double now_wall) {
  for (vda5050::Outgoing& out : v.master->take_messages()) {
    json message = vda5050::header(v.address, v.header_ids[out.name]++, now_wall);
    message.update(out.body);
    const std::string topic = vda5050::topic(v.address, out.name);
    bool published = false;
    if (out.name == "order" && v.grant_source_wall >= 0.0) {
      const double granted = v.grant_source_wall;
      v.grant_source_wall = -1.0;
      published = mqtt_->publish_acknowledged(topic, message.dump(), [this, granted] {
        const double latency = SimClock::wall_now() - granted;
        std::lock_guard lock(latency_mutex_);
        if (grant_to_broker_s_.size() < kLatencySamples) grant_to_broker_s_.push_back(latency);
      });
    } else {
      published = mqtt_->publish(topic, message.dump(), 1);
    }
    if (!published) {
      log_->warn("{}: could not publish {} (broker not connected)", v.master->id(), topic);
    } else if (out.name == "order") {
      log_->info("{}: order {} update {}: {} nodes, base through {}", v.master->id(),
                 message["orderId"].get<std::string>(), message["orderUpdateId"].get<std::uint32_t>(),
                 message["nodes"].size(), v.master->leg_order() ? v.master->leg_order()->released_through() : 0);
    }
  }
}

}  // namespace fleet::vda5050_bridge
