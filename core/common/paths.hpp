#pragma once

#include <optional>
#include <string>

namespace fleet {

/// Where config/ and maps/ live, the first that applies:
/// 1. $FLEET_HOME when set;
/// 2. an installed tree: the binary's own folder/FLEET_DATA_FROM_BIN (`../share/fleet` under
///    `cmake --install`, `/usr/share/fleet` from the Debian package) when it holds config/fleet.yaml;
/// 3. the source tree the binaries were built from.
std::string project_root();

/// config/fleet.yaml under the project root.
std::string default_config_path();
/// The configuration a site brings with its own fleets: config/sites/SITE.yaml (it may not exist).
std::string site_config_path(const std::string& site);
/// The configuration a program reads: `config_flag` when given; else the one the site of
/// `site_flag` brings, when it has one; else default_config_path().
std::string config_path_for(const std::optional<std::string>& config_flag, const std::optional<std::string>& site_flag);

/// maps/ under the project root.
std::string maps_dir();

/// Where Fleet writes (the server's database, the demo's and soak's run folders), the first that
/// applies: $FLEET_STATE_DIR; $FLEET_HOME/var; the source tree's var/ when the binaries run from
/// it; else $XDG_STATE_HOME/fleet, or ~/.local/state/fleet. Not created here.
std::string state_dir();

}  // namespace fleet
