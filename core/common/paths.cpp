#include "common/paths.hpp"

#include <cstdlib>

namespace fleet {

std::string project_root() {
  if (const char* home = std::getenv("FLEET_HOME"); home && *home) return home;
  return FLEET_SOURCE_DIR;
}

std::string default_config_path() { return project_root() + "/config/fleet.yaml"; }

std::string maps_dir() { return project_root() + "/maps"; }

}  // namespace fleet
