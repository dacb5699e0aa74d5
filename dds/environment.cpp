#include "dds/environment.hpp"

#include <cstdlib>

#include "common/paths.hpp"

namespace fleet::dds {

std::string use_fleet_dds_config() {
  if (const char* uri = std::getenv("CYCLONEDDS_URI"); uri && *uri) return uri;
  const std::string uri = "file://" + project_root() + "/config/cyclonedds.xml";
  setenv("CYCLONEDDS_URI", uri.c_str(), 1);
  return uri;
}

}  // namespace fleet::dds
