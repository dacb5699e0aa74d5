#include "common/paths.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace fleet {
namespace {

std::string env(const char* name) {
  const char* value = std::getenv(name);
  return value && *value ? value : "";
}

/// The installed data folder beside this binary, or "" when the binary is not installed.
std::string installed_data_dir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return "";
  const std::filesystem::path data = (exe.parent_path() / FLEET_DATA_FROM_BIN).lexically_normal();
  if (!std::filesystem::is_regular_file(data / "config" / "fleet.yaml", ec)) return "";
  return data.string();
}

}  // namespace

std::string project_root() {
  if (std::string home = env("FLEET_HOME"); !home.empty()) return home;
  // Looked up once: the binary does not move while it runs.
  static const std::string installed = installed_data_dir();
  if (!installed.empty()) return installed;
  return FLEET_SOURCE_DIR;
}

std::string default_config_path() {
  return project_root() + "/config/fleet.yaml";
}

std::string site_config_path(const std::string& site) {
  return project_root() + "/config/sites/" + site + ".yaml";
}

std::string config_path_for(const std::optional<std::string>& config_flag, const std::optional<std::string>& site_flag) {
  if (config_flag) return *config_flag;
  if (site_flag && std::filesystem::exists(site_config_path(*site_flag))) return site_config_path(*site_flag);
  return default_config_path();
}

std::string maps_dir() {
  return project_root() + "/maps";
}

std::string state_dir() {
  if (std::string dir = env("FLEET_STATE_DIR"); !dir.empty()) return dir;
  if (std::string home = env("FLEET_HOME"); !home.empty()) return home + "/var";
  if (project_root() == FLEET_SOURCE_DIR) return std::string(FLEET_SOURCE_DIR) + "/var";
  if (std::string xdg = env("XDG_STATE_HOME"); !xdg.empty()) return xdg + "/fleet";
  if (std::string home = env("HOME"); !home.empty()) return home + "/.local/state/fleet";
  return std::filesystem::temp_directory_path().string() + "/fleet";
}

}  // namespace fleet
