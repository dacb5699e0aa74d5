#pragma once

#include <string>

namespace fleet {

/// The project root, where config/ and maps/ live: $FLEET_HOME when set, else the source tree
/// the binaries were built from.
std::string project_root();

/// config/fleet.yaml under the project root.
std::string default_config_path();

/// maps/ under the project root.
std::string maps_dir();

}  // namespace fleet
