#include "map/site.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

#include "geometry/marker_sight.hpp"

namespace fleet::map {

namespace {

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  std::string at(const YAML::Node& node) const { return file_ + ":" + std::to_string(node.Mark().line + 1); }

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    throw MapError(at(node) + ": key '" + key + "': " + what);
  }

  void allow_keys(const YAML::Node& map, const std::string& key, const std::set<std::string>& allowed) const {
    if (!map.IsMap()) fail(map, key, "must be a map");
    for (const auto& item : map) {
      const std::string name = item.first.as<std::string>();
      if (!allowed.contains(name)) {
        throw MapError(at(item.first) + ": unknown key '" + (key.empty() ? name : key + "." + name) + "'");
      }
    }
  }

  double number(const YAML::Node& parent, const std::string& name, const std::string& key) const {
    const YAML::Node node = parent[name];
    const std::string full = key + "." + name;
    if (!node) throw MapError(at(parent) + ": key '" + full + "' is missing");
    return number_value(node, full);
  }

  double number_value(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) fail(node, key, "must be a number");
    double v = 0.0;
    try {
      v = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, key, "'" + node.Scalar() + "' is not a number");
    }
    if (!std::isfinite(v)) fail(node, key, "'" + node.Scalar() + "' is not finite");
    return v;
  }

  std::string text(const YAML::Node& parent, const std::string& name, const std::string& key) const {
    const YAML::Node node = parent[name];
    if (!node || !node.IsScalar() || node.Scalar().empty()) {
      throw MapError(at(parent) + ": key '" + key + "." + name + "' is missing");
    }
    return node.Scalar();
  }

  bool boolean(const YAML::Node& parent, const std::string& name, const std::string& key, bool def) const {
    const YAML::Node node = parent[name];
    if (!node) return def;
    try {
      return node.as<bool>();
    } catch (const YAML::Exception&) {
      fail(node, key + "." + name, "'" + node.Scalar() + "' is not true or false");
    }
  }

  const YAML::Node list(const YAML::Node& root, const std::string& key) const {
    const YAML::Node node = root[key];
    if (!node) return YAML::Node(YAML::NodeType::Sequence);
    if (!node.IsSequence()) fail(node, key, "must be a list");
    return node;
  }

  const std::string& file() const { return file_; }

 private:
  std::string file_;
};

geometry::Pose2 pose_of(const Reader& r, const YAML::Node& node, const std::string& key) {
  return {r.number(node, "x", key), r.number(node, "y", key), r.number(node, "yaw", key)};
}

void unique_id(const Reader& r, std::set<std::string>& seen, const std::string& id, const YAML::Node& node,
               const std::string& key) {
  if (!seen.insert(id).second) r.fail(node, key + ".id", "duplicate id '" + id + "'");
}

}  // namespace

const LoadingArea* Site::find_area(const std::string& id) const {
  for (const auto& a : loading_areas)
    if (a.id == id) return &a;
  return nullptr;
}

const StaticObstacle* Site::find_obstacle(const std::string& id) const {
  for (const auto& o : static_obstacles)
    if (o.id == id) return &o;
  return nullptr;
}

const Home* Site::find_home(const std::string& id) const {
  for (const auto& h : homes)
    if (h.id == id) return &h;
  return nullptr;
}

bool LoadingArea::offers(const std::string& action) const {
  return std::find(actions.begin(), actions.end(), action) != actions.end();
}

geometry::Pose2 LoadingArea::approach_pose(double distance) const {
  return {pose.x + distance * std::cos(pose.yaw), pose.y + distance * std::sin(pose.yaw),
          geometry::normalize_angle(pose.yaw + std::numbers::pi)};
}

std::vector<std::string> Site::area_ids() const {
  std::vector<std::string> ids;
  for (const auto& a : loading_areas) ids.push_back(a.id);
  return ids;
}

namespace {

geometry::Polygon polygon_of(const Reader& r, const YAML::Node& entry, const std::string& key, const std::string& what,
                             const geometry::Bounds& bounds) {
  const YAML::Node poly = entry["polygon"];
  if (!poly || !poly.IsSequence() || poly.size() < 3) {
    r.fail(entry, key + ".polygon", "must be a list of at least 3 [x, y] points");
  }
  geometry::Polygon polygon;
  for (std::size_t j = 0; j < poly.size(); ++j) {
    const std::string pkey = key + ".polygon[" + std::to_string(j) + "]";
    if (!poly[j].IsSequence() || poly[j].size() != 2) r.fail(poly[j], pkey, "must be [x, y]");
    const geometry::Vec2 p{r.number_value(poly[j][0], pkey), r.number_value(poly[j][1], pkey)};
    if (!bounds.contains(p)) r.fail(poly[j], pkey, what + " lies outside the bounds");
    polygon.push_back(p);
  }
  return polygon;
}

std::vector<std::string> actions_of(const Reader& r, const YAML::Node& entry, const std::string& key) {
  const YAML::Node node = entry["actions"];
  if (!node) return LoadingArea{}.actions;
  const std::string akey = key + ".actions";
  if (!node.IsSequence() || node.size() == 0) r.fail(node, akey, "must be a list of at least one action");
  const auto& known = place_action_names();
  std::string valid;
  for (const auto& name : known) valid += (valid.empty() ? "" : ", ") + name;
  std::vector<std::string> actions;
  for (std::size_t j = 0; j < node.size(); ++j) {
    const std::string name = node[j].IsScalar() ? node[j].Scalar() : std::string();
    const std::string jkey = akey + "[" + std::to_string(j) + "]";
    if (std::find(known.begin(), known.end(), name) == known.end()) {
      r.fail(node[j], jkey, "unknown action '" + name + "' (valid: " + valid + ")");
    }
    if (std::find(actions.begin(), actions.end(), name) != actions.end()) {
      r.fail(node[j], jkey, "action '" + name + "' is named twice");
    }
    actions.push_back(name);
  }
  return actions;
}

BoxStock boxes_of(const Reader& r, const YAML::Node& node, const std::string& key, const LoadingArea& area) {
  r.allow_keys(node, key, {"item", "count", "size", "mass"});
  if (!area.pallet_at_start) r.fail(node, key, "boxes need a pallet to stand on (pallet: true)");
  if (!area.offers("pickItem")) r.fail(node, key, "boxes are picked only where the place offers pickItem");
  BoxStock stock;
  stock.item = r.text(node, "item", key);
  const double count = r.number(node, "count", key);
  if (count < 1.0 || count != std::floor(count)) {
    r.fail(node["count"], key + ".count", "'" + node["count"].Scalar() + "' is not a whole number of boxes >= 1");
  }
  stock.count = static_cast<int>(count);
  const YAML::Node size = node["size"];
  if (size) {
    if (!size.IsSequence() || size.size() != 3) r.fail(size, key + ".size", "must be [length, width, height]");
    double* dims[] = {&stock.length, &stock.width, &stock.height};
    for (std::size_t j = 0; j < 3; ++j) {
      *dims[j] = r.number_value(size[j], key + ".size");
      if (!(*dims[j] > 0.0)) r.fail(size[j], key + ".size", "'" + size[j].Scalar() + "' is not a length > 0");
    }
  }
  if (node["mass"]) {
    stock.mass = r.number_value(node["mass"], key + ".mass");
    if (!(stock.mass > 0.0)) r.fail(node["mass"], key + ".mass", "'" + node["mass"].Scalar() + "' is not a mass > 0");
  }
  return stock;
}

void read_loading_areas(const Reader& r, const YAML::Node& root, Site& site) {
  std::set<std::string> ids;
  const YAML::Node areas = r.list(root, "loading_areas");
  for (std::size_t i = 0; i < areas.size(); ++i) {
    const std::string key = "loading_areas[" + std::to_string(i) + "]";
    r.allow_keys(areas[i], key, {"id", "x", "y", "yaw", "pallet", "actions", "height", "boxes"});
    LoadingArea area;
    area.id = r.text(areas[i], "id", key);
    area.pose = pose_of(r, areas[i], key);
    area.pallet_at_start = r.boolean(areas[i], "pallet", key, false);
    unique_id(r, ids, area.id, areas[i], key);
    if (!site.bounds.contains(area.pose.position()))
      r.fail(areas[i], key, "loading area '" + area.id + "' lies outside the bounds");
    area.actions = actions_of(r, areas[i], key);
    if (areas[i]["height"]) {
      area.height = r.number_value(areas[i]["height"], key + ".height");
      if (area.height < 0.0) {
        r.fail(areas[i]["height"], key + ".height",
               "'" + areas[i]["height"].Scalar() + "' is below the floor (must be >= 0)");
      }
    }
    if (areas[i]["boxes"]) area.boxes = boxes_of(r, areas[i]["boxes"], key + ".boxes", area);
    site.loading_areas.push_back(std::move(area));
  }
}

void read_obstacles_and_racks(const Reader& r, const YAML::Node& root, Site& site) {
  std::set<std::string> obstacle_ids;
  const YAML::Node obstacles = r.list(root, "static_obstacles");
  for (std::size_t i = 0; i < obstacles.size(); ++i) {
    const std::string key = "static_obstacles[" + std::to_string(i) + "]";
    r.allow_keys(obstacles[i], key, {"id", "polygon", "enabled"});
    StaticObstacle obstacle;
    obstacle.id = r.text(obstacles[i], "id", key);
    unique_id(r, obstacle_ids, obstacle.id, obstacles[i], key);
    obstacle.enabled_at_start = r.boolean(obstacles[i], "enabled", key, false);
    obstacle.polygon = polygon_of(r, obstacles[i], key, "obstacle '" + obstacle.id + "'", site.bounds);
    site.static_obstacles.push_back(std::move(obstacle));
  }
  std::set<std::string> rack_ids;
  const YAML::Node racks = r.list(root, "racks");
  for (std::size_t i = 0; i < racks.size(); ++i) {
    const std::string key = "racks[" + std::to_string(i) + "]";
    r.allow_keys(racks[i], key, {"id", "polygon"});
    Rack rack;
    rack.id = r.text(racks[i], "id", key);
    unique_id(r, rack_ids, rack.id, racks[i], key);
    rack.polygon = polygon_of(r, racks[i], key, "rack '" + rack.id + "'", site.bounds);
    site.racks.push_back(std::move(rack));
  }
}

/// The rack that covers `marker`'s face: the point a camera looks at (geometry::marker_sight_point)
/// lies in or on it. Nothing for a marker on a face.
const Rack* rack_in_front_of(const Site& site, const Marker& marker) {
  const geometry::Vec2 normal{std::cos(marker.pose.yaw), std::sin(marker.pose.yaw)};
  const geometry::Vec2 face = geometry::marker_sight_point(marker.pose);
  for (const Rack& rack : site.racks) {
    if (geometry::segment_intersects_polygon(face, face + 0.5 * normal, rack.polygon)) return &rack;
  }
  return nullptr;
}

void read_anchors_homes_markers(const Reader& r, const YAML::Node& root, Site& site) {
  std::set<std::string> anchor_ids;
  const YAML::Node anchors = r.list(root, "uwb_anchors");
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    const std::string key = "uwb_anchors[" + std::to_string(i) + "]";
    r.allow_keys(anchors[i], key, {"id", "x", "y", "z"});
    UwbAnchor anchor{r.text(anchors[i], "id", key), r.number(anchors[i], "x", key), r.number(anchors[i], "y", key),
                     r.number(anchors[i], "z", key)};
    unique_id(r, anchor_ids, anchor.id, anchors[i], key);
    site.uwb_anchors.push_back(std::move(anchor));
  }

  std::set<std::string> home_ids;
  const YAML::Node homes = r.list(root, "homes");
  for (std::size_t i = 0; i < homes.size(); ++i) {
    const std::string key = "homes[" + std::to_string(i) + "]";
    r.allow_keys(homes[i], key, {"id", "x", "y", "yaw"});
    Home home{r.text(homes[i], "id", key), pose_of(r, homes[i], key)};
    unique_id(r, home_ids, home.id, homes[i], key);
    if (!site.bounds.contains(home.pose.position()))
      r.fail(homes[i], key, "home '" + home.id + "' lies outside the bounds");
    site.homes.push_back(std::move(home));
  }

  std::set<std::string> marker_ids;
  const YAML::Node markers = r.list(root, "markers");
  for (std::size_t i = 0; i < markers.size(); ++i) {
    const std::string key = "markers[" + std::to_string(i) + "]";
    r.allow_keys(markers[i], key, {"id", "x", "y", "z", "yaw"});
    const YAML::Node id = markers[i]["id"];
    if (!id) throw MapError(r.at(markers[i]) + ": key '" + key + ".id' is missing");
    int code = -1;
    try {
      code = id.as<int>();
    } catch (const YAML::Exception&) {
      r.fail(id, key + ".id", "'" + id.Scalar() + "' is not a whole number");
    }
    if (code < 0) r.fail(id, key + ".id", "'" + id.Scalar() + "' is negative");
    unique_id(r, marker_ids, std::to_string(code), markers[i], key);
    Marker marker{code, pose_of(r, markers[i], key), 0.0};
    if (markers[i]["z"]) marker.z = r.number_value(markers[i]["z"], key + ".z");
    if (!site.bounds.contains(marker.pose.position()))
      r.fail(markers[i], key, "marker " + std::to_string(code) + " lies outside the bounds");
    if (const Rack* buried = rack_in_front_of(site, marker)) {
      r.fail(markers[i], key,
             "marker " + std::to_string(code) + " lies inside rack " + buried->id +
                 ": no camera sees its face; put it on the rack's face, facing out (yaw)");
    }
    site.markers.push_back(marker);
  }
}

}  // namespace

Packing packing_of(const Reader& r, const YAML::Node& node, const Site& site) {
  const std::string key = "packing";
  r.allow_keys(node, key, {"boxes_per_pallet", "stations", "full_pallets_to", "empty_pallets_from"});
  Packing packing;
  const double boxes = r.number(node, "boxes_per_pallet", key);
  if (boxes < 1.0 || boxes != std::floor(boxes)) {
    r.fail(node["boxes_per_pallet"], key + ".boxes_per_pallet",
           "'" + node["boxes_per_pallet"].Scalar() + "' is not a whole number of boxes >= 1");
  }
  packing.boxes_per_pallet = static_cast<int>(boxes);
  // Each list names places that offer what the chain does there.
  const auto places = [&](const std::string& name, std::vector<std::string> needs) {
    const std::string list_key = key + "." + name;
    const YAML::Node list = node[name];
    if (!list) throw MapError(r.at(node) + ": key '" + list_key + "' is missing");
    if (!list.IsSequence() || list.size() == 0) r.fail(list, list_key, "must be a list of place ids");
    std::vector<std::string> ids;
    for (std::size_t j = 0; j < list.size(); ++j) {
      const std::string jkey = list_key + "[" + std::to_string(j) + "]";
      if (!list[j].IsScalar()) r.fail(list[j], jkey, "must be a place id");
      const std::string id = list[j].Scalar();
      const LoadingArea* area = site.find_area(id);
      if (!area) r.fail(list[j], jkey, "unknown place '" + id + "'");
      for (const auto& action : needs) {
        if (!area->offers(action)) r.fail(list[j], jkey, "place '" + id + "' does not offer " + action);
      }
      if (std::find(ids.begin(), ids.end(), id) != ids.end())
        r.fail(list[j], jkey, "place '" + id + "' is named twice");
      ids.push_back(id);
    }
    return ids;
  };
  packing.stations = places("stations", {"pick", "drop", "dropItem"});
  packing.full_pallets_to = places("full_pallets_to", {"drop"});
  packing.empty_pallets_from = places("empty_pallets_from", {"pick"});
  return packing;
}

Site parse_site(const std::string& yaml_text, const std::string& path) {
  const Reader r(path);
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw MapError(path + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
  if (!root.IsMap()) throw MapError(path + ": expected a map of keys at the top level");
  r.allow_keys(root, "",
               {"name", "opendrive", "bounds", "road_width", "graph_spacing", "approach_distance", "loading_areas",
                "static_obstacles", "uwb_anchors", "homes", "racks", "markers", "packing", "variant_of"});

  Site site;
  site.file = path;
  site.name = std::filesystem::path(path).stem().string();
  if (root["name"]) site.name = r.text(root, "name", "");
  if (root["variant_of"]) site.variant_of = r.text(root, "variant_of", "");
  if (root["opendrive"]) {
    const std::filesystem::path xodr(r.text(root, "opendrive", ""));
    site.opendrive_file = (xodr.is_absolute() ? xodr : std::filesystem::path(path).parent_path() / xodr).string();
  }

  const YAML::Node bounds = root["bounds"];
  if (!bounds) throw MapError(path + ": key 'bounds' is missing");
  r.allow_keys(bounds, "bounds", {"min_x", "min_y", "max_x", "max_y"});
  site.bounds = {r.number(bounds, "min_x", "bounds"), r.number(bounds, "min_y", "bounds"),
                 r.number(bounds, "max_x", "bounds"), r.number(bounds, "max_y", "bounds")};
  if (!(site.bounds.max_x > site.bounds.min_x) || !(site.bounds.max_y > site.bounds.min_y)) {
    r.fail(bounds, "bounds", "max must be greater than min");
  }
  const auto positive = [&](const char* key, double& value) {
    if (!root[key]) return;
    value = r.number_value(root[key], key);
    if (!(value > 0.0)) r.fail(root[key], key, "must be positive");
  };
  positive("road_width", site.road_width);
  positive("graph_spacing", site.graph_spacing);
  positive("approach_distance", site.approach_distance);

  read_loading_areas(r, root, site);
  read_obstacles_and_racks(r, root, site);
  read_anchors_homes_markers(r, root, site);
  if (root["packing"]) site.packing = packing_of(r, root["packing"], site);
  return site;
}

Site load_site(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw MapError(path + ": cannot open the site file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_site(buffer.str(), path);
}

std::string site_path(const std::string& maps_dir, const std::string& name) {
  return (std::filesystem::path(maps_dir) / (name + ".yaml")).string();
}

std::vector<std::string> site_names(const std::string& maps_dir) {
  std::vector<std::string> names;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(maps_dir, error)) {
    if (entry.path().extension() == ".yaml") names.push_back(entry.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::string revision_mismatch(const Site& site, const Site& candidate) {
  constexpr double kTolerance = 1e-6;  // metres / radians: the same numbers, as written
  auto same_pose = [](const geometry::Pose2& a, const geometry::Pose2& b) {
    return std::abs(a.x - b.x) <= kTolerance && std::abs(a.y - b.y) <= kTolerance &&
           std::abs(a.yaw - b.yaw) <= kTolerance;
  };
  const std::string who = candidate.name + " is not a revision of " + site.name + ": ";
  if (std::abs(site.bounds.min_x - candidate.bounds.min_x) > kTolerance ||
      std::abs(site.bounds.min_y - candidate.bounds.min_y) > kTolerance ||
      std::abs(site.bounds.max_x - candidate.bounds.max_x) > kTolerance ||
      std::abs(site.bounds.max_y - candidate.bounds.max_y) > kTolerance) {
    return who + "its bounds differ";
  }
  if (site.loading_areas.size() != candidate.loading_areas.size()) return who + "it has other loading areas";
  for (const auto& area : site.loading_areas) {
    const LoadingArea* other = candidate.find_area(area.id);
    if (!other) return who + "loading area " + area.id + " is missing";
    if (!same_pose(area.pose, other->pose)) return who + "loading area " + area.id + " stands elsewhere";
    if (std::abs(area.height - other->height) > kTolerance || area.actions != other->actions) {
      return who + "loading area " + area.id + " holds its load at another height or offers other actions";
    }
  }
  if (site.homes.size() != candidate.homes.size()) return who + "it has other homes";
  for (const auto& home : site.homes) {
    const Home* other = candidate.find_home(home.id);
    if (!other) return who + "home " + home.id + " is missing";
    if (!same_pose(home.pose, other->pose)) return who + "home " + home.id + " is elsewhere";
  }
  if (site.uwb_anchors.size() != candidate.uwb_anchors.size()) return who + "it has other UWB anchors";
  for (std::size_t i = 0; i < site.uwb_anchors.size(); ++i) {
    const auto& a = site.uwb_anchors[i];
    const auto& b = candidate.uwb_anchors[i];
    if (a.id != b.id || std::abs(a.x - b.x) > kTolerance || std::abs(a.y - b.y) > kTolerance ||
        std::abs(a.z - b.z) > kTolerance) {
      return who + "UWB anchor " + a.id + " differs";
    }
  }
  return "";
}

std::vector<std::string> site_revisions(const Site& site) {
  std::vector<std::string> names{site.name};
  std::vector<std::filesystem::path> files;
  const std::filesystem::path dir = std::filesystem::path(site.file).parent_path();
  for (const auto& entry : std::filesystem::directory_iterator(dir.empty() ? "." : dir)) {
    if (entry.path().extension() == ".yaml" && entry.path().stem() != site.name) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    try {
      const Site candidate = load_site(file.string());
      if (candidate.variant_of.empty() && revision_mismatch(site, candidate).empty()) names.push_back(candidate.name);
    } catch (const std::exception&) {
      // Not a site file, or a broken one: `fleetctl map check` names what is wrong with it.
    }
  }
  return names;
}

}  // namespace fleet::map
