#include "cli/fleet_run.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "cli/client.hpp"
#include "cli/command_flags.hpp"
#include "cli/commands.hpp"
#include "cli/vda5050_vehicles.hpp"
#include "common/args.hpp"
#include "common/clock.hpp"
#include "common/paths.hpp"
#include "dds/security.hpp"
#include "map/site.hpp"
#include "model/names.hpp"
#include "security/security_folder.hpp"
#include "vehicle/vehicle_types.hpp"

namespace fleet::cli {

namespace {
std::string tail_of(const std::string& file, std::size_t lines) {
  std::ifstream in(file);
  std::vector<std::string> all;
  for (std::string line; std::getline(in, line);) all.push_back(line);
  std::string out;
  for (std::size_t i = all.size() > lines ? all.size() - lines : 0; i < all.size(); ++i) out += "  " + all[i] + "\n";
  return out;
}

std::string timestamp() {
  const std::time_t t = std::time(nullptr);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y%m%d-%H%M%S", std::gmtime(&t));
  return buffer;
}
}  // namespace

std::string random_token() {
  std::random_device device;
  char out[33];
  for (int i = 0; i < 4; ++i) std::snprintf(out + 8 * i, 9, "%08x", device());
  return out;
}

FleetRun::FleetRun(RunOptions options, config::FleetConfig config, Logger log)
    : options_(std::move(options)), config_(std::move(config)), log_(std::move(log)) {
  if (options_.whole_tracks) tracks_ = monitor::TrackRecorder(options_.duration_s * options_.time_scale + 60.0);
  const map::Site site = map::load_site(map::site_path(maps_dir(), options_.site));
  // What the server and agents will do with the same files: robots declared by count need a home
  // each, and a site with too few stops the run here, before any process starts.
  std::vector<std::string> homes;
  for (const map::Home& home : site.homes) homes.push_back(home.id);
  config::assign_homes(config_, homes, site.name);
  std::size_t agent_robots = 0;
  for (const auto& [fleet, robot] : config_.all_robots()) {
    const vehicle::RobotType* type = vehicle::find_robot_type(fleet->robot_type);
    if (type == nullptr || type->agent_driven) ++agent_robots;
  }
  if (options_.agents < 1 || options_.agents > static_cast<int>(agent_robots)) {
    throw ArgError("--agents " + std::to_string(options_.agents) + ": " + config_.source + " declares " +
                   std::to_string(agent_robots) + " robots driven by fleet-agent; choose 1 .. " +
                   std::to_string(agent_robots));
  }
  if (options_.vda5050_vehicles > 0) pick_vda5050_vehicles(config_, options_.vda5050_vehicles);  // checked early
  // Round robin over the fleets, so that N agents bring every fleet of the site (fk1, rt1, fk2, ...).
  for (std::size_t index = 0; static_cast<int>(robot_ids_.size()) < options_.agents; ++index) {
    for (const auto& fleet : config_.fleets) {
      const vehicle::RobotType* type = vehicle::find_robot_type(fleet.robot_type);
      if (type != nullptr && !type->agent_driven) continue;  // fleet-vda5050 drives them
      if (index < fleet.robots.size() && static_cast<int>(robot_ids_.size()) < options_.agents) {
        robot_ids_.push_back(fleet.robots[index].id);
      }
    }
  }
  watch_pickers_in_aisles(site);
  run_dir_ = state_dir() + "/runs/" + options_.kind + "-" + timestamp() + "-" + std::to_string(getpid());
  std::filesystem::create_directories(run_dir_);
}

void FleetRun::watch_pickers_in_aisles(const map::Site& site) {
  std::vector<std::string> pickers;
  for (const auto& id : robot_ids_) {
    const auto robot = config_.find_robot(id);
    if (robot && robot->first->robot_type == "picker") pickers.push_back(id);
  }
  if (pickers.size() < 2) return;
  std::vector<std::pair<std::string, geometry::Polygon>> racks;
  for (const auto& rack : site.racks) racks.emplace_back(rack.id, rack.polygon);
  auto aisles = monitor::rack_aisles(racks);
  if (!aisles.empty()) aisle_share_.emplace(std::move(aisles), std::move(pickers));
}

FleetRun::~FleetRun() {
  stop();
}

std::string FleetRun::binary(const std::string& name) const {
  return (std::filesystem::read_symlink("/proc/self/exe").parent_path() / name).string();
}

void FleetRun::throw_if_a_process_ended() {
  for (std::size_t i : processes_.reap()) {
    const auto& child = processes_.children()[i];
    throw std::runtime_error(child.name + " " + ProcessGroup::describe(child.exit_status) + "; its log " +
                             child.log_file + " ends with:\n" + tail_of(child.log_file, 10));
  }
}

std::vector<std::string> FleetRun::server_command(const std::vector<std::string>& common, const std::string& db,
                                                  int http_port) const {
  std::vector<std::string> argv{binary("fleet-server")};
  argv.insert(argv.end(), common.begin(), common.end());
  if (options_.auto_orders) argv.push_back("--auto-orders");
  argv.insert(argv.end(), {"--db", db, "--http-port", std::to_string(http_port)});
  if (!options_.api_token.empty()) argv.insert(argv.end(), {"--api-token", options_.api_token});
  // With a security folder the web view is served over HTTPS with the folder's web certificate.
  if (!dds::security_folder().empty() && http_port > 0) {
    const security::FolderLayout folder(dds::security_folder());
    argv.insert(argv.end(), {"--http-tls-cert", folder.web_certificate(), "--http-tls-key", folder.web_key()});
  }
  argv.insert(argv.end(), options_.extra_server_args.begin(), options_.extra_server_args.end());
  return argv;
}

void FleetRun::start_standby(const std::vector<std::string>& common) {
  std::vector<std::string> argv;
  std::istringstream words(options_.standby_wrap);
  for (std::string w; words >> w;) argv.push_back(w);
  // Its web view is on the port after the active one's: read-only while it stands by.
  const std::vector<std::string> server =
      server_command(common, run_dir_ + "/standby.db", options_.http_port > 0 ? options_.http_port + 1 : 0);
  argv.insert(argv.end(), server.begin(), server.end());
  argv.insert(argv.end(), {"--standby", "--set", "server.id=server-2"});
  servers_["server-2"] = processes_.start("fleet-server-2", argv, run_dir_ + "/fleet-server-2.log");
}

std::optional<double> FleetRun::grants_from_a_new_writer_since(double since) const {
  std::optional<double> first;
  for (const auto& [writer, heard_wall] : grant_writers_) {
    if (heard_wall > since && (!first || heard_wall < *first)) first = heard_wall;
  }
  return first;
}

void FleetRun::start() {
  participant_ = std::make_unique<dds::Participant>(options_.domain);
  order_reader_ = std::make_unique<dds::Reader<model::OrderInfo>>(*participant_, dds::qos::latched_state());
  truth_reader_ = std::make_unique<dds::Reader<model::SimTruth>>(*participant_, dds::qos::live_state(),
                                                                 dds::robot_report_partitions());
  state_reader_ = std::make_unique<dds::Reader<model::RobotState>>(*participant_, dds::qos::live_state(),
                                                                   dds::robot_report_partitions());
  grant_reader_ = std::make_unique<dds::Reader<model::TrafficGrant>>(*participant_, dds::qos::live_state(),
                                                                     model::every_robot_partition());
  server_load_reader_ = std::make_unique<dds::Reader<model::ServerLoad>>(*participant_, dds::qos::live_state());

  std::vector<std::string> common{"--config",     options_.config_file,
                                  "--domain",     std::to_string(options_.domain),
                                  "--site",       options_.site,
                                  "--time-scale", std::to_string(options_.time_scale),
                                  "--seed",       std::to_string(options_.seed)};
  // Each process presents its own credentials from the folder fleetctl presents the operator's.
  if (!dds::security_folder().empty()) common.insert(common.end(), {"--security", dds::security_folder()});
  std::vector<std::string> server_argv = server_command(common, run_dir_ + "/fleet.db", options_.http_port);
  if (options_.standby) server_argv.insert(server_argv.end(), {"--set", "server.id=server-1"});
  processes_.start("fleet-server", server_argv, run_dir_ + "/fleet-server.log");
  if (options_.standby) servers_["server-1"] = kServerIndex;
  // One agent starts when the one before it publishes its state: an agent's start (its site, grids
  // and OctoMap) costs a few tenths of a CPU second, and 48 of them at once held the two cores for
  // seconds, the first agents' control steps with them.
  dds::Reader<model::RobotState> came_up(*participant_, dds::qos::live_state(), dds::robot_report_partitions());
  std::set<std::string> up;
  const auto wait_until_up = [&](const std::string& id) {
    const auto give_up = std::chrono::steady_clock::now() + kAgentStartWait;
    while (!up.contains(id) && std::chrono::steady_clock::now() < give_up && !stop_requested()) {
      came_up.take_data([&](model::RobotState&& state) { up.insert(state.robot_id); });
      throw_if_a_process_ended();
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  };
  for (const auto& id : robot_ids_) {
    std::vector<std::string> argv;
    if (!options_.agent_wrap.empty()) {
      // The server is child 0, so the agents number 1..N in start order.
      const std::string number = std::to_string(processes_.children().size());
      std::istringstream words(options_.agent_wrap);
      for (std::string w; words >> w;) {
        for (auto at = w.find("{n}"); at != std::string::npos; at = w.find("{n}")) w.replace(at, 3, number);
        argv.push_back(w);
      }
    }
    argv.insert(argv.end(), {binary("fleet-agent"), "--id", id});
    argv.insert(argv.end(), common.begin(), common.end());
    argv.insert(argv.end(), options_.extra_agent_args.begin(), options_.extra_agent_args.end());
    processes_.start("fleet-agent " + id, argv, run_dir_ + "/fleet-agent-" + id + ".log");
    wait_until_up(id);
  }
  if (options_.vda5050_vehicles > 0) {
    std::vector<std::string> bridge_argv{binary("fleet-vda5050")};
    bridge_argv.insert(bridge_argv.end(), common.begin(), common.end());
    bridge_argv.insert(bridge_argv.end(), options_.extra_agent_args.begin(), options_.extra_agent_args.end());
    const map::Site site = map::load_site(map::site_path(maps_dir(), options_.site));
    vda5050_ = start_vda5050_vehicles(processes_, config_, site, options_.vda5050_vehicles, options_.time_scale,
                                      bridge_argv, run_dir_);
    log_->info("{} simulated VDA 5050 vehicles ({}) on the run's broker {}", vda5050_.robot_ids.size(),
               model::join(vda5050_.robot_ids), vda5050_.broker);
    for (const auto& id : vda5050_.robot_ids) wait_until_up(id);
  }
  if (options_.standby) start_standby(common);
  started_ = std::chrono::steady_clock::now();
  start_sim_ = SimClock(options_.time_scale).now();

  FleetClient probe(options_.domain);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!probe.find_server(std::chrono::milliseconds(200))) {
    throw_if_a_process_ended();
    if (std::chrono::steady_clock::now() > deadline) {
      throw std::runtime_error("fleet-server did not appear on DDS domain " + std::to_string(options_.domain) +
                               " within 15 s; see " + run_dir_);
    }
  }
}

bool FleetRun::poll() {
  order_reader_->take_data([&](model::OrderInfo&& info) {
    // What each robot works on, for the deadlock watch: its open order and phase.
    const bool open = info.state == "ASSIGNED" || info.state == "ACTIVE";
    for (auto& [robot, task] : task_of_) {
      if (task.starts_with(std::to_string(info.order_id) + "/") && (!open || robot != info.robot_id)) task.clear();
    }
    if (open && !info.robot_id.empty()) task_of_[info.robot_id] = std::to_string(info.order_id) + "/" + info.phase;
    orders_[info.order_id] = std::move(info);
  });
  state_reader_->take_data([&](model::RobotState&& state) {
    progress_.note_state(state.robot_id, state.task_state, state.sim_time);
    // Standing by design: a loader waiting for its transporter (whose watch goes on), an arm at
    // work, a stacker holding its pallet where its order has it stand.
    if (state.detail == model::kDetailWaitsForTransporter || state.detail.starts_with("arm ") ||
        state.task_state == "HOLDING") {
      works_standing_.insert(state.robot_id);
    } else {
      works_standing_.erase(state.robot_id);
    }
    localization_.note_estimate(state.robot_id, state.pose, state.sim_time);
    if (state.control_period > 0.0) {
      control_lag_[state.robot_id] = {state.robot_id, state.control_lag_p50, state.control_lag_p99,
                                      state.control_period, state.control_steps_skipped};
    }
    // Beside each robot's true track, where it believed it was: a report's tracks show both.
    if (geometry::is_finite(state.pose)) tracks_.add(state.robot_id + "/estimate", state.pose, state.sim_time);
    report_far_off_estimates();
  });
  // Who waits for whom, so a robot queued behind robots that move is not taken for a deadlock.
  grant_reader_->take([&](model::TrafficGrant&& grant, const dds::SampleInfo& info) {
    if (!info.valid_data) return;
    grant_writers_.try_emplace(info.publication_handle, SimClock::wall_now());
    progress_.note_waiting_for(grant.robot_id, std::move(grant.blocked_by));
  });
  server_load_reader_->take_data([&](model::ServerLoad&& load) {
    if (load.active) active_server_ = load.server_id;
  });
  truth_reader_->take_data([&](model::SimTruth&& truth) {
    tracks_.add(truth.robot_id, truth.pose, truth.sim_time);
    localization_.note_truth(truth.robot_id, truth.pose, truth.sim_time);
    report_far_off_estimates();
    if (aisle_share_) aisle_share_->note(truth.robot_id, truth.pose.position(), truth.sim_time);
    if (progress_.update(truth.robot_id, truth.pose, task_of_[truth.robot_id], truth.sim_time,
                         works_standing_.contains(truth.robot_id))) {
      const auto& d = progress_.deadlocks().back();
      std::string waits;
      for (const auto& other : d.waiting_for) waits += (waits.empty() ? "; it waits for " : ", ") + other;
      log_->warn("deadlock: {} made no progress on order {} for {:.0f} s sim at ({:.3f}, {:.3f}){}", d.robot_id, d.task,
                 d.detected - d.since, d.pose.x, d.pose.y, waits);
      write_tracks("deadlock-" + std::to_string(progress_.deadlocks().size()) + "-" + d.robot_id, 90.0, truth.sim_time);
    }
    // The true shape is the robot's fleet's footprint polygon; SimTruth carries only its extent.
    const auto robot = config_.find_robot(truth.robot_id);
    const geometry::Polygon body =
        robot ? robot->first->profile.footprint : geometry::footprint_polygon({0.0, 0.0, 0.0}, truth.footprint);
    for (const auto& c : collisions_.update(truth.robot_id, truth.pose, body, truth.sim_time)) {
      log_->warn(
          "collision at t={:.2f} s sim: {} at ({:.3f}, {:.3f}, yaw {:.2f}) and {} at ({:.3f}, {:.3f}, yaw {:.2f})",
          c.sim_time - start_sim_, c.robot_a, c.pose_a.x, c.pose_a.y, c.pose_a.yaw, c.robot_b, c.pose_b.x, c.pose_b.y,
          c.pose_b.yaw);
      write_tracks("collision-" + std::to_string(collisions_.collisions().size()) + "-" + c.robot_a + "-" + c.robot_b,
                   30.0, truth.sim_time);
    }
  });
  for (std::size_t i : processes_.reap()) {
    const auto& child = processes_.children()[i];
    if (expected_exits_.erase(i) != 0) continue;  // ended by an injected fault
    const std::string what = child.name + " " + ProcessGroup::describe(child.exit_status);
    crashes_.push_back(what);
    log_->error("{} on its own; its log {} ends with:\n{}", what, child.log_file, tail_of(child.log_file, 5));
  }
  if (stop_requested()) return false;
  if (options_.duration_s > 0.0 && wall_seconds() >= options_.duration_s) return false;
  return true;
}

void FleetRun::stop() {
  if (stopped_ || !participant_) return;
  stopped_ = true;
  ended_ = std::chrono::steady_clock::now();
  // Read the final order states while the server still serves them.
  const auto drain_until = std::chrono::steady_clock::now() + std::chrono::milliseconds(300);
  while (std::chrono::steady_clock::now() < drain_until) {
    order_reader_->take_data([&](model::OrderInfo&& info) { orders_[info.order_id] = std::move(info); });
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  processes_.reap();
  processes_.stop_all(5.0);
  if (options_.whole_tracks) write_tracks("tracks", sim_seconds() + 60.0, start_sim_ + sim_seconds());
}

void FleetRun::report_far_off_estimates() {
  for (const auto& off : localization_.take_far_off()) {
    ++estimates_far_off_;
    const auto& at = off.at;
    log_->warn(
        "localization: {} believes it is at ({:.2f}, {:.2f}), {:.2f} m from where it is ({:.2f}, {:.2f}), at t={:.1f} "
        "s sim",
        off.robot_id, at.estimate.x, at.estimate.y, at.error, at.truth.x, at.truth.y, at.sim_time - start_sim_);
    write_tracks("localization-" + std::to_string(estimates_far_off_) + "-" + off.robot_id, 90.0, at.sim_time);
  }
}

void FleetRun::write_tracks(const std::string& name, double seconds, double now_sim) {
  const std::string file = run_dir_ + "/" + name + ".csv";
  std::ofstream out(file);
  tracks_.write_csv(out, now_sim - seconds, start_sim_);
  if (!out) {
    log_->error("could not write the robots' tracks to {}", file);
    return;
  }
  log_->warn("the robots' tracks of the last {:.0f} s sim: {}", seconds, file);
}

double FleetRun::wall_seconds() const {
  const auto end = stopped_ ? ended_ : std::chrono::steady_clock::now();
  return std::chrono::duration<double>(end - started_).count();
}

double FleetRun::sim_seconds() const {
  return wall_seconds() * options_.time_scale;
}

std::string fleet_counts(const std::map<std::string, long>& counts) {
  std::string out;
  for (const auto& [fleet, count] : counts) out += (out.empty() ? "" : ", ") + fleet + " " + std::to_string(count);
  return out;
}

std::map<std::string, long> FleetRun::done_by_fleet() const {
  std::map<std::string, long> done;
  for (const auto& fleet : config_.fleets) done[fleet.id] = 0;
  for (const auto& [id, order] : orders_) {
    if (order.state != "DONE") continue;
    if (const auto robot = config_.find_robot(order.robot_id)) ++done[robot->first->id];
  }
  return done;
}

std::map<std::string, monitor::ErrorFigures> FleetRun::localization_by_fleet() const {
  std::map<std::string, std::string> fleets;
  for (const auto& robot_id : robot_ids_) fleets[robot_id] = fleet_of(robot_id);
  return monitor::error_figures(localization_.errors(), fleets);
}

std::string FleetRun::fleet_of(const std::string& robot_id) const {
  const auto robot = config_.find_robot(robot_id);
  return robot ? robot->first->id : std::string();
}

monitor::OrderTally FleetRun::tally() const {
  return monitor::tally_orders(orders_, 1);
}

int demo_command(const CommandArgs& command, std::ostream& out, std::ostream& err, std::uint32_t domain) {
  const CommandFlags args("demo", "", command.args);
  RunOptions options;
  config::FleetConfig config = config::load_fleet_config(command.config_file);
  options.config_file = command.config_file;
  options.domain = domain;
  options.agents = static_cast<int>(args.integer("agents").value_or(4));
  options.site = args.value("site").value_or(config.settings.get_string("site"));
  options.duration_s = args.number("duration").value_or(0.0);
  options.time_scale = args.number("time-scale").value_or(config.settings.get_double("time_scale"));
  options.seed = args.integer("seed").value_or(config.settings.get_int("seed"));
  options.http_port = static_cast<int>(args.integer("http-port").value_or(config.settings.get_int("server.http_port")));
  options.api_token = random_token();
  options.auto_orders = !args.flag("no-auto-orders");
  options.vda5050_vehicles = static_cast<int>(args.integer("vda5050-vehicles").value_or(0));
  options.standby = args.flag("standby");
  if (!std::filesystem::exists(map::site_path(maps_dir(), options.site))) {
    throw ArgError("--site: " + model::unknown_name_message("site", options.site, map::site_names(maps_dir())));
  }
  {
    FleetClient probe(domain);
    if (probe.find_server(std::chrono::milliseconds(1200))) {
      throw ArgError("a fleet-server already runs on DDS domain " + std::to_string(domain) +
                     "; stop it or choose another --domain");
    }
  }

  install_stop_handlers();
  auto log = make_logger("fleetctl demo");
  FleetRun run(options, config, log);
  run.start();
  err << "Fleet demo: fleet-server and " << options.agents << " fleet-agents (" << model::join(run.robot_ids()) << ")"
      << (run.vda5050_robot_ids().empty()
              ? std::string()
              : ", " + std::to_string(run.vda5050_robot_ids().size()) + " simulated VDA 5050 vehicles (" +
                    model::join(run.vda5050_robot_ids()) + ")")
      << " on DDS domain " << domain << ", site " << options.site << ", time scale " << options.time_scale
      << ", automatic orders " << (options.auto_orders ? "on" : "off") << ".\n"
      << "  logs:    " << run.run_dir() << "/\n"
      << (options.http_port > 0
              ? "  web:     " + std::string(dds::security_folder().empty() ? "http" : "https") +
                    "://127.0.0.1:" + std::to_string(options.http_port) + "/?token=" + options.api_token + "\n"
              : std::string())
      << (options.standby ? "  standby: server-2 mirrors server-1 and takes over when it is gone" +
                                std::string(options.http_port > 0
                                                ? " (its web view on port " + std::to_string(options.http_port + 1) +
                                                      ", read-only until then)"
                                                : "") +
                                "; fleetctl --domain " + std::to_string(domain) + " servers\n"
                          : std::string())
      << "  watch:   fleetctl --domain " << domain << " robots\n"
      << "  order:   fleetctl --domain " << domain << " inject --count 1 --wait   (one order the fleet can take now)\n"
      << "  by hand: fleetctl --domain " << domain << " order add --from AREA --to AREA --wait"
      << (options.auto_orders ? "   (with fleetctl auto-orders off first, the pallets stay where you see them)" : "")
      << "\n"
      << (options.duration_s > 0 ? "  stops after " + std::to_string(static_cast<int>(options.duration_s)) + " s"
                                 : std::string("  Ctrl-C stops it"))
      << "\n";
  double next_progress = 10.0;
  std::size_t stalls_told = 0;
  while (run.poll()) {
    // A stall (an open order without progress for the watch's timeout) is told when seen: it
    // is what an operator must act on, and a quiet demo hides it.
    for (const auto& stalls = run.progress().deadlocks(); stalls_told < stalls.size(); ++stalls_told) {
      const auto& d = stalls[stalls_told];
      err << "  STALL at t=" << static_cast<int>(d.detected - run.start_sim()) << " s sim: " << d.robot_id
          << " made no progress on order " << d.task << " for " << static_cast<int>(d.detected - d.since)
          << " s sim, at (" << std::fixed << std::setprecision(2) << d.pose.x << ", " << d.pose.y << ")\n"
          << std::defaultfloat;
    }
    if (run.wall_seconds() >= next_progress) {
      const auto t = run.tally();
      err << "  t=" << static_cast<int>(run.sim_seconds()) << " s sim: " << t.done << " orders done, " << t.open
          << " open, " << t.failed << " failed, " << run.collisions().size() << " collisions, "
          << run.progress().deadlocks().size() << " stalls\n";
      next_progress += 10.0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  run.stop();
  const auto t = run.tally();
  nlohmann::json stalls = nlohmann::json::array();
  for (const auto& d : run.progress().deadlocks()) {
    stalls.push_back({{"robot", d.robot_id},
                      {"order", d.task},
                      {"since_sim_s", std::round((d.since - run.start_sim()) * 10) / 10},
                      {"at", {std::round(d.pose.x * 1000) / 1000, std::round(d.pose.y * 1000) / 1000}}});
  }
  nlohmann::json summary{{"orders_created", t.created},
                         {"orders_done", t.done},
                         {"orders_failed", t.failed},
                         {"orders_cancelled", t.cancelled},
                         {"orders_open", t.open},
                         {"orders_lost", t.lost},
                         {"orders_done_by_fleet", run.done_by_fleet()},
                         {"collisions", run.collisions().size()},
                         {"stalls", stalls.size()},
                         {"stalled", stalls},
                         {"agents", options.agents},
                         {"site", options.site},
                         {"sim_seconds", std::round(run.sim_seconds() * 10) / 10},
                         {"wall_seconds", std::round(run.wall_seconds() * 10) / 10},
                         {"time_scale", options.time_scale},
                         {"domain", domain},
                         {"crashed", run.crashes()},
                         {"control_lag_worst", control_lag_json(run.worst_control_lag())},
                         {"run_dir", run.run_dir()}};
  if (command.json) {
    out << summary.dump() << "\n";
  } else {
    out << "Fleet demo summary (" << summary["sim_seconds"] << " s sim, " << summary["wall_seconds"] << " s wall)\n"
        << "  orders: " << t.created << " created, " << t.done << " done, " << t.failed << " failed, " << t.cancelled
        << " cancelled, " << t.open << " open, " << t.lost << " lost\n"
        << "  done per fleet: " << fleet_counts(run.done_by_fleet()) << "\n"
        << "  collisions: " << run.collisions().size() << "\n"
        << "  stalls (an open order without progress for 60 s sim): " << stalls.size() << "\n"
        << "  control lag (worst agent, sim s): " << summary["control_lag_worst"].dump() << "\n"
        << "  processes that ended on their own: " << (run.crashes().empty() ? "none" : model::join(run.crashes()))
        << "\n  logs: " << run.run_dir() << "/\n";
  }
  return (t.lost == 0 && run.crashes().empty()) ? kExitOk : kExitFailed;
}

std::optional<ControlLag> FleetRun::worst_control_lag() const {
  std::optional<ControlLag> worst;
  for (const auto& [robot, lag] : control_lag_) {
    if (!worst || lag.p99_s / lag.period_s > worst->p99_s / worst->period_s) worst = lag;
  }
  return worst;
}

std::map<std::string, double> FleetRun::control_lag_p99_by_fleet() const {
  std::map<std::string, double> worst;
  for (const auto& [robot_id, lag] : control_lag_) {
    const auto robot = config_.find_robot(robot_id);
    if (!robot) continue;
    double& w = worst[robot->first->id];
    w = std::max(w, lag.p99_s);
  }
  return worst;
}

nlohmann::json control_lag_json(const std::optional<ControlLag>& lag) {
  if (!lag) return nlohmann::json::object();
  return {{"robot", lag->robot},
          {"p50_s", round_to(lag->p50_s, 0.0001)},
          {"p99_s", round_to(lag->p99_s, 0.0001)},
          {"period_s", round_to(lag->period_s, 0.0001)},
          {"steps_skipped", lag->steps_skipped}};
}

double round_to(double v, double step) {
  return std::round(v / step) / std::round(1.0 / step);
}

}  // namespace fleet::cli
