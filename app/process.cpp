#include "app/process.hpp"

#include <signal.h>

#include <filesystem>

#include "common/errors.hpp"
#include "common/paths.hpp"
#include "common/process_memory.hpp"
#include "dds/environment.hpp"
#include "dds/security.hpp"
#include "model/names.hpp"
#include "security/credentials.hpp"

namespace fleet::app {

namespace {

std::atomic<bool> g_stop{false};

void on_stop_signal(int) {
  g_stop = true;
}

}  // namespace

std::optional<config::FleetConfig> read_config(Args& args, const char* help, std::ostream& out) {
  if (args.flag("help")) {
    out << help;
    return std::nullopt;
  }
  const std::string config_path = config_path_for(args.value("config"), args.peek("site"));
  config::FleetConfig config = config::load_fleet_config(config_path);
  config::apply_common_flags(args, config);
  return config;
}

spdlog::level::level_enum finish_args(Args& args) {
  const bool verbose = args.flag("verbose");
  if (const auto rest = args.positionals(); !rest.empty()) throw ArgError("unexpected argument '" + rest[0] + "'");
  return verbose ? spdlog::level::debug : spdlog::level::info;
}

std::shared_ptr<const map::SiteMap> load_site(config::FleetConfig& config, const std::vector<std::string>& robot_ids) {
  const std::string site = config.settings.get_string("site");
  const std::string site_file = map::site_path(maps_dir(), site);
  if (!std::filesystem::exists(site_file)) {
    throw InputError("site: " + model::unknown_name_message("site", site, map::site_names(maps_dir())) + " (" +
                     maps_dir() + "/NAME.yaml)");
  }
  auto site_map = std::make_shared<const map::SiteMap>(map::load_site_map(site_file));
  std::vector<std::string> homes;
  for (const map::Home& home : site_map->site.homes) homes.push_back(home.id);
  config::assign_homes(config, homes, site);
  for (const std::string& id : robot_ids) {
    const config::RobotSpec* robot = config.find_robot(id)->second;
    if (!site_map->site.find_home(robot->home)) {
      throw config::ConfigError(config.source + ": robot '" + robot->id + "': home '" + robot->home +
                                "' is not a home of " + site_file);
    }
  }
  return site_map;
}

const std::atomic<bool>& install_stop_handlers() {
  // SA_RESTART: a signal interrupts no system call of the DDS threads, as with std::signal.
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  action.sa_flags = SA_RESTART;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  return g_stop;
}

bool stop_requested() {
  return g_stop.load();
}

const std::atomic<bool>& start_daemon() {
  dds::use_fleet_dds_config();
  ProcessMemory::limit_arenas();
  return install_stop_handlers();
}

void use_dds_security(const std::string& folder, const std::string& identity, const std::string& origin) {
  if (folder.empty()) return;
  try {
    dds::use_security(folder, identity);
  } catch (const security::SecurityError& e) {
    throw InputError(origin + ": " + e.what());
  }
}

int exit_code_of_current_exception(const std::string& program, std::ostream& err, bool help_hint) {
  try {
    throw;
  } catch (const ArgError& e) {
    err << program << ": " << e.what() << (help_hint ? " (see --help)" : "") << "\n";
    return 2;
  } catch (const InputError& e) {
    err << program << ": " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    err << program << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace fleet::app
