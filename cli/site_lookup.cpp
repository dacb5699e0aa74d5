#include <algorithm>
#include <filesystem>

#include "commands.hpp"
#include "common/errors.hpp"
#include "map/site.hpp"
#include "model/names.hpp"

namespace fleet::cli {

std::vector<std::string> site_names(const std::string& source_dir) {
  return map::site_names((std::filesystem::path(source_dir.empty() ? "." : source_dir) / "maps").string());
}

std::string known_site_path(const std::string& source_dir, const std::string& name) {
  const std::string maps = (std::filesystem::path(source_dir.empty() ? "." : source_dir) / "maps").string();
  const std::string path = map::site_path(maps, name);
  if (!std::filesystem::exists(path)) {
    throw InputError(model::unknown_name_message("site", name, site_names(source_dir)) + " (maps/NAME.yaml)");
  }
  return path;
}

}  // namespace fleet::cli
