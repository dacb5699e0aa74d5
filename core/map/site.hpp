#pragma once

#include <optional>
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

/// The actions a place may offer, by their VDA 5050 names: `pick` and `drop` a load (a pallet),
/// `pickItem` and `dropItem` for an arm that takes single items (boxes) from or onto a load there.
inline const std::vector<std::string>& place_action_names() {
  static const std::vector<std::string> names{"pick", "drop", "pickItem", "dropItem"};
  return names;
}

/// Where a pallet stands and which way it faces ("location and direction of the loading area and
/// their ids" [Forklift thesis, section 3]). `pose.yaw` points from the pallet towards the side a forklift
/// approaches from, so a forklift picks facing `yaw + pi`.
/// Boxes of one item standing on the pallet at a rack place, for picking by items [Picker thesis,
/// section 4.4: pallets of marked boxes of at most 5 kg]. One item per pallet, as a warehouse
/// stores a pallet per article.
struct BoxStock {
  std::string item;     ///< the article's code, as pick lines name it
  int count = 0;        ///< boxes on the pallet
  double length = 0.3;  ///< one box, metres
  double width = 0.3;
  double height = 0.25;
  double mass = 3.0;  ///< kg
};

struct LoadingArea {
  std::string id;
  geometry::Pose2 pose;
  bool pallet_at_start = false;
  /// What a vehicle may do here (place_action_names); a site file that names none offers pick and drop.
  std::vector<std::string> actions{"pick", "drop"};
  /// Height of the load above the floor, metres: 0 on the floor, more on a rack level or platform;
  /// only a vehicle that lifts that high handles it.
  double height = 0.0;
  /// The boxes on its pallet, where the site declares them (a place that offers pickItem).
  std::optional<BoxStock> boxes;

  bool offers(const std::string& action) const;
  /// Where a vehicle stands to handle the load: `distance` out from the place towards the road
  /// (along its yaw), facing the place.
  geometry::Pose2 approach_pose(double distance) const;
};

/// Packing stations: pallets on places that pickers fill with boxes. A pallet holding
/// `boxes_per_pallet` boxes is full: it goes to one of `full_pallets_to`, and an empty pallet from
/// one of `empty_pallets_from` takes its place.
struct Packing {
  int boxes_per_pallet = 0;
  std::vector<std::string> stations;  ///< in the order pick tours move on to the next free one
  std::vector<std::string> full_pallets_to;
  std::vector<std::string> empty_pallets_from;
};

/// An AR marker at a known pose, for localisation by markers [Picker thesis, section 4.2.9]: on
/// posts every 10 m in open areas and on rack pillars every 3.5 m.
struct Marker {
  int id = 0;            ///< the code printed on the marker, unique on the site
  geometry::Pose2 pose;  ///< yaw: the direction the marker faces
  double z = 0.0;        ///< height of its centre above the floor, metres
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
  /// A place's centre to where a vehicle stands on the road to handle its load, metres: 0.30 for
  /// the tables' forklifts, about a pallet and half a vehicle on a real-scale site.
  double approach_distance = 0.30;
  std::vector<LoadingArea> loading_areas;
  std::vector<StaticObstacle> static_obstacles;
  std::vector<UwbAnchor> uwb_anchors;
  std::vector<Home> homes;
  std::vector<Rack> racks;
  std::vector<Marker> markers;
  std::optional<Packing> packing;
  /// Non-empty: this file is a design variant of the named site, kept to compare designs
  /// (`fleetctl traffic-eval --against`), not a state of the site robots are switched to.
  std::string variant_of;

  const LoadingArea* find_area(const std::string& id) const;
  const StaticObstacle* find_obstacle(const std::string& id) const;
  const Home* find_home(const std::string& id) const;
  std::vector<std::string> area_ids() const;
};

/// Reads and validates a site file. Throws MapError naming the file, line and key for unknown
/// keys, missing or non-numeric values, duplicate ids, obstacles outside the area, unknown
/// actions and negative heights.
Site load_site(const std::string& path);

/// The same from YAML text; `path` names it in messages and resolves the .xodr.
Site parse_site(const std::string& yaml_text, const std::string& path);

/// Why `candidate` is not a revision of `site` — another map of the same physical site that robots
/// can be switched to at runtime: the same bounds, loading areas (ids and poses), homes and UWB
/// anchors; roads and obstacles may differ. Empty when it is one.
std::string revision_mismatch(const Site& site, const Site& candidate);

/// `site` itself and every revision of it among the site files in its folder, by name: the maps a
/// server of `site` can switch its robots to. Files that do not load and design variants
/// (`variant_of`) are left out.
std::vector<std::string> site_revisions(const Site& site);

/// maps/<name>.yaml under `maps_dir`.
std::string site_path(const std::string& maps_dir, const std::string& name);

/// The names of the site files (*.yaml, without the extension) in `maps_dir`, sorted; none when
/// the folder cannot be read. For messages that name the sites there are.
std::vector<std::string> site_names(const std::string& maps_dir);

}  // namespace fleet::map
