#pragma once

#include <spdlog/common.h>

#include <atomic>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "common/args.hpp"
#include "config/fleet_config.hpp"
#include "map/site_map.hpp"

namespace fleet::app {

/// The start of a daemon's command line: --help prints `help` to `out` and gives nothing;
/// otherwise --config (default config/fleet.yaml) is read and the flags every Fleet process
/// shares are applied to it (config::apply_common_flags).
std::optional<config::FleetConfig> read_config(Args& args, const char* help, std::ostream& out);

/// The end of a daemon's command line: --verbose as the log level; ArgError for anything left.
spdlog::level::level_enum finish_args(Args& args);

/// The configured site (maps/<site>.yaml) with its road network and graph, loaded once for the
/// process. Robots declared by count get their homes from it (config::assign_homes); ConfigError
/// naming the robot when the home of one of `robot_ids` is not in it.
std::shared_ptr<const map::SiteMap> load_site(config::FleetConfig& config, const std::vector<std::string>& robot_ids);

/// SIGINT and SIGTERM set a flag instead of ending the process; the flag is returned.
const std::atomic<bool>& install_stop_handlers();
/// Whether SIGINT or SIGTERM came since install_stop_handlers().
bool stop_requested();

/// What a daemon does once its command line is good, before any thread starts: points
/// CYCLONEDDS_URI at the shipped configuration (dds::use_fleet_dds_config), limits malloc's
/// arenas and installs the stop handlers. Returns the flag its loop runs until.
const std::atomic<bool>& start_daemon();

/// With a security `folder` (--security DIR, dds.security), every participant the process creates
/// presents the credentials of `identity` from it (dds::use_security); InputError, prefixed by
/// `origin` (where the folder was named), naming the file that is missing, unreadable, expired or
/// from another authority. An empty folder: nothing.
void use_dds_security(const std::string& folder, const std::string& identity, const std::string& origin);

/// dds.domain, time_scale and seed of `config` into a process's options.
template <class Options>
void set_run_options(Options& options, const config::FleetConfig& config) {
  options.domain = static_cast<std::uint32_t>(config.settings.get_int("dds.domain"));
  options.time_scale = config.settings.get_double("time_scale");
  options.seed = static_cast<std::uint64_t>(config.settings.get_int("seed"));
}

/// For the `catch (...)` around a main: prints "<program>: <message>" to `err` and returns the
/// exit code, 2 for bad input (InputError, ArgError among them) and 1 for any other
/// std::exception. `help_hint` adds " (see --help)" to an ArgError. Anything that is not a
/// std::exception is thrown on.
int exit_code_of_current_exception(const std::string& program, std::ostream& err, bool help_hint);

}  // namespace fleet::app
