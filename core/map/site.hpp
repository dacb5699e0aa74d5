#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "geometry/polygon.hpp"

namespace fleet::map {

/// A map or site input error; the message names the file, line and key.
class MapError : public InputError {
 public:
  using InputError::InputError;
};

/// Where a pallet stands and which way it faces ("location and direction of the loading area and
/// their ids" [Forklift thesis, section 3]). `pose.yaw` points from the pallet towards the side a forklift
/// approaches from, so a forklift picks facing `yaw + pi`.
struct LoadingArea {
  std::string id;
  geometry::Pose2 pose;
  bool pallet_at_start = false;
};

/// A designated static obstacle the user switches on and off [Forklift thesis, section 3].
struct StaticObstacle {
  std::string id;
  geometry::Polygon polygon;
  bool enabled_at_start = false;
};

/// A permanent structure beside the roads (a rack row) [Picker thesis]: drawn, and never crossed by a
/// road (check_site_map refuses a site whose roads run through one).
struct Rack {
  std::string id;
  geometry::Polygon polygon;
};

struct UwbAnchor {
  std::string id;
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

struct Home {
  std::string id;
  geometry::Pose2 pose;
};

/// A site file, maps/NAME.yaml: the road network it uses and what stands around it.
struct Site {
  std::string name;             ///< file stem, e.g. "table_a"
  std::string file;             ///< path of the site file
  std::string opendrive_file;   ///< path of the .xodr, resolved relative to the site file
  geometry::Bounds bounds;      ///< the area, metres
  double road_width = 0.30;     ///< metres
  double graph_spacing = 0.10;  ///< road-graph sample spacing, metres
  std::vector<LoadingArea> loading_areas;
  std::vector<StaticObstacle> static_obstacles;
  std::vector<UwbAnchor> uwb_anchors;
  std::vector<Home> homes;
  std::vector<Rack> racks;

  const LoadingArea* find_area(const std::string& id) const;
  const StaticObstacle* find_obstacle(const std::string& id) const;
  const Home* find_home(const std::string& id) const;
  std::vector<std::string> area_ids() const;
};

/// Reads and validates a site file. Throws MapError naming the file, line and key for unknown
/// keys, missing or non-numeric values, duplicate ids and obstacles outside the area.
Site load_site(const std::string& path);

/// The same from YAML text; `path` names it in messages and resolves the .xodr.
Site parse_site(const std::string& yaml_text, const std::string& path);

/// Why `candidate` is not a revision of `site` — another map of the same physical site that robots
/// can be switched to at runtime: the same bounds, loading areas (ids and poses), homes and UWB
/// anchors; roads and obstacles may differ. Empty when it is one.
std::string revision_mismatch(const Site& site, const Site& candidate);

/// `site` itself and every revision of it among the site files in its folder, by name: the maps a
/// server of `site` can switch its robots to. Files that do not load are left out.
std::vector<std::string> site_revisions(const Site& site);

/// maps/<name>.yaml under `maps_dir`.
std::string site_path(const std::string& maps_dir, const std::string& name);

/// The names of the site files (*.yaml, without the extension) in `maps_dir`, sorted; none when
/// the folder cannot be read. For messages that name the sites there are.
std::vector<std::string> site_names(const std::string& maps_dir);

}  // namespace fleet::map
